// The Mitsuba materials' kernels (bsdf_microfacet.h): microfacet normalisation (D and the
// visible normals), sampling against the pdf (chi-square), pdf integrals, the sample's f
// and pdf against evaluation, reciprocity, energy, and closed forms (conductor Fresnel,
// thin slab, plastic albedo), and that each kind reads only the sample numbers it declares.
#include <catch2/catch.hpp>

#include <cstring>
#include <memory>

#include "chi2.h"
#include "kernels/bsdf.h"
#include "kernels/fresnel.h"
#include "stages/core/bsdf_dispatch.h"

using namespace wmlt;
using chi2::close;
using chi2::dirAt;

namespace {
constexpr double kMinP = 1e-3;

// A material of kind k over its own constants.
struct Material {
    BsdfExtra x;
    BsdfParams p;
    Material(MaterialKind k, MicrofacetType t, float alpha, float eta = 1.5f) {
        x.dist = Microfacet{t, alpha};
        p.kind = k;
        p.eta = eta;
        p.reflect = Vec3(1.0f);
        p.refract = Vec3(1.0f);
        p.diffuse = Vec3(0.5f, 0.3f, 0.8f);
        if (k == MaterialKind::Conductor || k == MaterialKind::RoughConductor)  // copper (veach-mis)
            setConductorIndex(p, Vec3(0.200438f, 0.924033f, 1.10221f), Vec3(3.91295f, 2.45285f, 2.14219f));
        x.specularWeight = 0.5f;
        if (k == MaterialKind::Plastic || k == MaterialKind::RoughPlastic) preparePlastic(x, eta, k == MaterialKind::RoughPlastic);
        p.x = &x;
        if (k == MaterialKind::Blend)
            setParts(Material(MaterialKind::RoughConductor, t, alpha), Material(MaterialKind::RoughPlastic, t, 0.15f, 1.49f), 0.3f);
    }
    // A blend (blendbsdf) of a and b, b with weight w.
    void setParts(const Material& a, const Material& b, float w) {
        p.kind = MaterialKind::Blend;
        p.blendWeight = w;
        parts = std::make_shared<std::vector<Material>>(std::vector<Material>{a, b});
        partParams[0] = (*parts)[0].p;
        partParams[1] = (*parts)[1].p;
        x.blendParts = partParams;
    }
    Material(const Material& o) : x(o.x), p(o.p), parts(o.parts) {
        p.x = &x;
        partParams[0] = o.partParams[0];
        partParams[1] = o.partParams[1];
        if (parts) x.blendParts = partParams;
    }
    std::shared_ptr<std::vector<Material>> parts;  // a blend's (their params point into them)
    BsdfParams partParams[2];
};

std::vector<Material> roughCases() {
    std::vector<Material> v;
    for (MicrofacetType t : {MicrofacetType::Beckmann, MicrofacetType::GGX}) {
        v.emplace_back(MaterialKind::RoughConductor, t, 0.1f);
        v.emplace_back(MaterialKind::RoughConductor, t, 0.5f);
        v.emplace_back(MaterialKind::RoughDielectric, t, 0.2f, 1.5f);
        v.emplace_back(MaterialKind::RoughDielectric, t, 0.6f, 1.0f / 1.33f);
        v.emplace_back(MaterialKind::RoughPlastic, t, 0.15f, 1.49f);
    }
    v.emplace_back(MaterialKind::Plastic, MicrofacetType::Beckmann, 0.1f, 1.49f);
    // Blends: rough conductor and rough plastic; rough dielectric (transmits: the adjoint in
    // importance mode) and matte; the smooth plastic's delta coating and a rough conductor.
    v.emplace_back(MaterialKind::Blend, MicrofacetType::GGX, 0.3f);
    v.push_back(v.back());
    v.back().setParts(Material(MaterialKind::RoughDielectric, MicrofacetType::Beckmann, 0.2f, 1.5f),
                      Material(MaterialKind::Matte, MicrofacetType::GGX, 0.1f), 0.6f);
    v.push_back(v.back());
    v.back().setParts(Material(MaterialKind::Plastic, MicrofacetType::Beckmann, 0.1f, 1.49f),
                      Material(MaterialKind::RoughConductor, MicrofacetType::GGX, 0.5f), 0.5f);
    return v;
}
const char* name(const Material& m) {
    static const char* n[] = {"matte", "", "", "", "conductor", "rough conductor", "rough dielectric", "thin", "plastic", "rough plastic", "blend"};
    return n[int(m.p.kind)];
}

// Integral of pdf over the sphere (bins about the mirror direction, fine enough for alpha >= 0.1).
double pdfIntegral(const Material& m, Vec3 wo) {
    double s = 0;
    for (double v : chi2::SphereBins::uniform(Vec3(-wo.x, -wo.y, wo.z), 24, 16).integrate([&](Vec3 w) { return bsdfPdf(m.p, wo, w); }, 1e-8, 10))
        s += v;
    return s;
}
}  // namespace

TEST_CASE("Microfacet D and the visible normals are normalised", "[bsdf][microfacet]") {
    for (MicrofacetType t : {MicrofacetType::Beckmann, MicrofacetType::GGX})
        for (float a : {0.1f, 0.3f, 0.8f}) {
            Microfacet d{t, a};
            double s = 0;  // projected area: int D(m) cos dm = 1
            for (double v :
                 chi2::SphereBins::uniform({0, 0, 1}, 40, 4).integrate([&](Vec3 m) { return microfacetD(d, m) * std::max(0.0f, m.z); }, 1e-9, 12))
                s += v;
            INFO("type " << int(t) << " alpha " << a);
            CHECK(s == Approx(1.0).margin(2e-4));
            for (double th : {0.0, 40.0, 75.0, 89.0, 140.0}) {  // Smith's Lambda is exact: int D_wo = 1
                Vec3 wo = dirAt(th, 30);
                double v = 0;
                for (double x : chi2::SphereBins::uniform({0, 0, 1}, 40, 16).integrate([&](Vec3 m) { return visibleNormalPdf(d, wo, m); }, 1e-9, 10))
                    v += x;
                INFO("theta " << th);
                CHECK(v == Approx(1.0).margin(2e-4));
            }
        }
}

TEST_CASE("Visible normal sampling matches D_wo (chi-square)", "[bsdf][microfacet][chi2]") {
    int k = 0;
    for (MicrofacetType t : {MicrofacetType::Beckmann, MicrofacetType::GGX})
        for (float a : {0.05f, 0.3f, 1.0f})
            for (double th : {0.0, 45.0, 80.0, 89.5, 120.0}) {
                Microfacet d{t, a};
                Vec3 wo = dirAt(th, 70);
                auto sample = [&](chi2::Pcg32& g, Vec3& w) {
                    w = sampleVisibleNormal(d, wo, g.uniform(), g.uniform());
                    return true;
                };
                auto r = chi2::sphereTest(
                    sample, [&](Vec3 m) { return visibleNormalPdf(d, wo, m); }, chi2::SphereBins::lobe({0, 0, 1}, 2 / (a * a), 12, 2, 16), 200000, 0,
                    40 + k++);
                INFO("type " << int(t) << " alpha " << a << " theta " << th << " " << chi2::describe(r));
                CHECK(r.pValue > kMinP);
            }
}

TEST_CASE("Microfacet BSDFs: sampling matches the pdf, f/pdf of samples equal evaluation", "[bsdf][microfacet][chi2]") {
    int k = 0, mismatches = 0;
    for (const Material& m : roughCases())
        for (double th : {10.0, 70.0, 150.0}) {
            Vec3 wo = dirAt(th, 200);
            // (the mode changes only the rough dielectric's f, not the directions)
            for (TransportMode mode : {TransportMode::Radiance, TransportMode::Importance}) {
                if (mode == TransportMode::Importance && m.p.kind != MaterialKind::RoughDielectric && m.p.kind != MaterialKind::Blend) continue;
                auto sample = [&](chi2::Pcg32& g, Vec3& w) {
                    BsdfSample s;
                    float ul = g.uniform(), u1 = g.uniform(), u2 = g.uniform();
                    if (!bsdfSample(m.p, wo, ul, u1, u2, mode, s) || s.delta) return false;
                    Vec3 f = mode == TransportMode::Radiance ? bsdfF(m.p, wo, s.wi) : bsdfF(m.p, s.wi, wo);
                    for (int c = 0; c < 3; ++c) mismatches += !close(s.f[c], f[c]);
                    mismatches += !close(s.pdf, bsdfPdf(m.p, wo, s.wi)) || !isFinite(s.f);
                    w = s.wi;
                    return true;
                };
                // Failed samples (below the surface, or the plastic's delta coating) form the
                // extra bin: their mass is 1 - the pdf's integral.
                auto r = chi2::sphereTest(
                    sample, [&](Vec3 w) { return bsdfPdf(m.p, wo, w); }, chi2::SphereBins::uniform(Vec3(-wo.x, -wo.y, wo.z), 24, 16), 100000,
                    std::max(0.0, 1.0 - pdfIntegral(m, wo)), 300 + k++);
                INFO(name(m) << " type " << int(m.x.dist.type) << " alpha " << m.x.dist.alphaX << " eta " << m.p.eta << " theta " << th << " "
                             << chi2::describe(r));
                CHECK(r.pValue > kMinP);
            }
        }
    CHECK(mismatches == 0);
}

TEST_CASE("Microfacet BSDF pdfs integrate to at most 1, to 1 where nothing is lost", "[bsdf][microfacet][pdf]") {
    for (const Material& m : roughCases()) {
        for (double th : {0.0, 30.0, 70.0, 160.0}) {
            const double s = pdfIntegral(m, dirAt(th, 25));
            INFO(name(m) << " alpha " << m.x.dist.alphaX << " eta " << m.p.eta << " theta " << th << " integral " << s);
            CHECK(s <= 1 + 1e-4);
            // Near normal incidence a rough dielectric, conductor or rough plastic loses
            // < 1% (samples shadowed below the horizon); the smooth plastic loses its coating.
            if (m.p.kind == MaterialKind::Plastic) {
                const double F = fresnelDielectric(std::fabs(dirAt(th, 0).z), m.p.eta);
                CHECK(s == Approx(1 - F * 0.5 / (F * 0.5 + (1 - F) * 0.5)).margin(1e-4));
            } else if (th == 0.0 && m.x.dist.alphaX <= 0.2f) {
                CHECK(s >= 0.99);
            }
        }
    }
}

TEST_CASE("Microfacet BSDFs are reciprocal (rough dielectric: up to eta'^2)", "[bsdf][microfacet][reciprocity]") {
    chi2::Pcg32 g(11);
    int bad = 0, nonzero = 0;
    for (const Material& m : roughCases())
        for (int i = 0; i < 20000; ++i) {
            Vec3 wo = sampleUniformSphere(g.uniform(), g.uniform()), wi = sampleUniformSphere(g.uniform(), g.uniform());
            // f(wi, wo) = f(wo, wi) eta'^2, eta' = n(wi side) / n(wo side) (Veach 1997, 5.2),
            // for a rough dielectric (a blend: each part with its own factor).
            auto reversed = [&](const BsdfParams& q) {
                float e2 = 1;
                if (q.kind == MaterialKind::RoughDielectric && wo.z * wi.z < 0) e2 = wo.z > 0 ? q.eta * q.eta : 1 / (q.eta * q.eta);
                return bsdfF(q, wo, wi) * e2;
            };
            const Vec3 a = m.p.kind == MaterialKind::Blend
                               ? reversed(m.partParams[0]) * (1 - m.p.blendWeight) + reversed(m.partParams[1]) * m.p.blendWeight
                               : reversed(m.p);
            const Vec3 b = bsdfF(m.p, wi, wo);
            for (int c = 0; c < 3; ++c) {
                bool ok = close(a[c], b[c], 1e-3);
                if (!ok && bad < 3)
                    WARN(name(m) << " alpha " << m.x.dist.alphaX << " wo " << wo.x << " " << wo.y << " " << wo.z << " wi " << wi.x << " " << wi.y
                                 << " " << wi.z << ": " << a[c] << " vs " << b[c]);
                bad += !ok;
            }
            nonzero += a[1] > 0;
        }
    CHECK(bad == 0);
    CHECK(nonzero > 40000);
}

TEST_CASE("Microfacet BSDFs conserve energy, closed forms of the albedo", "[bsdf][microfacet][energy]") {
    int k = 0;
    for (const Material& m : roughCases())
        for (double th : {0.0, 80.0, 135.0})
            for (TransportMode mode : {TransportMode::Radiance, TransportMode::Importance}) {
                Vec3 wo = dirAt(th, 40);
                chi2::Pcg32 g(900 + k++);
                const int N = 50000;
                double s[3] = {0, 0, 0}, s2[3] = {0, 0, 0};
                for (int i = 0; i < N; ++i) {
                    BsdfSample bs;
                    if (!bsdfSample(m.p, wo, g.uniform(), g.uniform(), g.uniform(), mode, bs)) continue;
                    Vec3 w = bs.f * (absCosTheta(bs.wi) / bs.pdf);
                    for (int c = 0; c < 3; ++c) {
                        s[c] += w[c];
                        s2[c] += double(w[c]) * w[c];
                    }
                }
                for (int c = 0; c < 3; ++c) {
                    double mean = s[c] / N, se = std::sqrt(std::max(0.0, s2[c] / N - mean * mean) / N);
                    INFO(name(m) << " alpha " << m.x.dist.alphaX << " eta " << m.p.eta << " theta " << th << " mode " << int(mode) << " channel " << c
                                 << " albedo " << mean << " se " << se);
                    // Radiance across a dielectric is not conserved (1/eta^2): only Importance.
                    const bool transmits = m.p.kind == MaterialKind::RoughDielectric ||
                                           (m.p.kind == MaterialKind::Blend && m.partParams[0].kind == MaterialKind::RoughDielectric);
                    if (!(transmits && mode == TransportMode::Radiance)) CHECK(mean <= 1 + 5 * se + 1e-5);
                    if (m.p.kind == MaterialKind::Plastic) {  // F Ks + (1 - F) Kd with the exact Fdr
                        double F = fresnelDielectric(std::fabs(wo.z), m.p.eta);
                        CHECK(std::fabs(mean - (F + (1 - F) * m.p.diffuse[c])) <= 5 * se + 1e-4);
                    }
                }
            }
}

TEST_CASE("Conductor Fresnel: normal incidence, k = 0, the perfect mirror", "[bsdf][fresnel]") {
    for (float n : {0.2f, 1.5f, 2.8656f})
        for (float kk : {0.0f, 1.0f, 3.9f}) {
            double r0 = ((n - 1) * (n - 1) + kk * kk) / ((n + 1) * (n + 1) + kk * kk);
            CHECK(fresnelComplex(1.0f, n, kk) == Approx(r0).epsilon(1e-5));
            CHECK(fresnelComplex(0.0f, n, kk) == Approx(1.0).epsilon(1e-5));  // grazing
        }
    for (int i = 1; i <= 100; ++i) {
        float c = i / 100.0f;
        CHECK(fresnelComplex(c, 1.5f, 0.0f) == Approx(fresnelDielectric(c, 1.5f)).margin(1e-6));
        CHECK(fresnelComplex(c, 0.0f, 1.0f) == Approx(1.0).margin(1e-6));  // Mitsuba's "none"
    }
}

TEST_CASE("Delta Mitsuba kinds: conductor and thin dielectric weights and directions", "[bsdf][delta]") {
    Material cu(MaterialKind::Conductor, MicrofacetType::Beckmann, 0.1f);
    Material thin(MaterialKind::ThinDielectric, MicrofacetType::Beckmann, 0.1f, 1.5f);
    for (double th : {0.0, 40.0, 85.0, 130.0}) {
        Vec3 wo = dirAt(th, 15);
        BsdfSample s;
        REQUIRE(bsdfSample(cu.p, wo, 0.5f, 0.5f, 0.5f, TransportMode::Radiance, s));
        CHECK((s.delta && s.wi.x == -wo.x && s.wi.z == wo.z));
        Vec3 F = fresnelConductor(std::fabs(wo.z), conductorEta(cu.p), conductorK(cu.p)), w = s.f * absCosTheta(s.wi) / s.pdf;
        for (int c = 0; c < 3; ++c) CHECK(w[c] == Approx(F[c]).epsilon(1e-5));
        double Fd = fresnelDielectric(std::fabs(wo.z), 1.5f), R = 2 * Fd / (1 + Fd);
        int nRefl = 0;
        chi2::Pcg32 g(3);
        for (int i = 0; i < 20000; ++i) {
            REQUIRE(bsdfSample(thin.p, wo, g.uniform(), 0.5f, 0.5f, TransportMode::Radiance, s));
            bool refl = s.wi.z == wo.z;
            nRefl += refl;
            if (!refl) CHECK((s.wi.x == -wo.x && s.wi.y == -wo.y && s.wi.z == -wo.z));  // straight through
            CHECK(s.f[0] * absCosTheta(s.wi) / s.pdf == Approx(1.0).epsilon(1e-5));     // white slab
        }
        CHECK(std::fabs(nRefl / 20000.0 - R) <= 5 * std::sqrt(R * (1 - R) / 20000) + 1e-9);
    }
}

// BsdfOf<K>::reads (stages/core/bsdf_dispatch.h) says which of a sample's numbers the kind reads:
// the stages ask for only those, and MMLT proposes only those, so a number declared unread
// must never change a sample. Each kind, both transport modes, 2000 random draws: the
// sample with the unread numbers replaced by other values is the same bit for bit.
TEST_CASE("BSDF kinds read only the sample numbers they declare", "[bsdf]") {
    uint64_t state = 0x5eed;
    auto next = [&] {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return float(state >> 40) * 0x1p-24f;
    };
    forEachMaterialKind([&](auto kind) {
        constexpr MaterialKind K = decltype(kind)::value;
        using B = BsdfOf<K>;
        Material m(K, MicrofacetType::GGX, 0.3f, 1.5f);
        m.p.specular = Vec3(0.3f);
        m.p.shininess = 20;
        INFO("kind " << int(K) << ", reads " << int(B::reads));
        for (TransportMode mode : {TransportMode::Radiance, TransportMode::Importance})
            for (int i = 0; i < 2000; ++i) {
                const Vec3 wo = normalize(Vec3(next() - 0.5f, next() - 0.5f, next() - (i % 2 ? 0.0f : 1.0f)));
                const float u[3] = {next(), next(), next()};
                const float other[3] = {next(), next(), next()};
                BsdfSample a, b;
                const bool okA = B::sample(m.p, wo, u[0], u[1], u[2], mode, a);
                const bool lobe = B::reads & kReadsLobe, dir = B::reads & kReadsDirection;
                const bool okB = B::sample(m.p, wo, lobe ? u[0] : other[0], dir ? u[1] : other[1], dir ? u[2] : other[2], mode, b);
                REQUIRE(okA == okB);
                if (!okA) continue;
                REQUIRE(std::memcmp(&a.wi, &b.wi, sizeof a.wi) == 0);
                REQUIRE(std::memcmp(&a.f, &b.f, sizeof a.f) == 0);
                REQUIRE(std::memcmp(&a.pdf, &b.pdf, sizeof a.pdf) == 0);
                REQUIRE(a.delta == b.delta);
            }
    });
}
