// The coated BSDF (kernels/bsdf_coated.cpp: pbrt-v4's layered BSDF by random walks): its
// sampled weights and its f are estimators of one BSDF, so the albedo from sampling
// (the mean of f |cos| / pdf) equals the integral of f |cos| over the hemisphere (uniform
// directions), within the estimators' measured noise; a lossless slab (a smooth coat over a
// white base, no absorption) conserves energy; the functions are deterministic (MMLT's
// replay) and two-sided; pbrt-v4's render of a coated scene: test_pbrt_scenes.cpp. And
// pbrt-v4's own exit weighting (a switch, off) breaks the first property. And
// DiffuseTransmission (pbrt's diffusetransmission): its sample's density is its pdf, which
// integrates to 1 over the sphere, and f / pdf is its weight.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "kernels/bsdf.h"
#include "kernels/sampling.h"

using namespace wmlt;

namespace {

struct Coat {
    BsdfExtra x;
    BsdfParams m;
    Coat(bool conductor, float coatAlpha, float baseAlpha, float thickness, Vec3 R = Vec3(1.0f), int maxDepth = 10) {
        x.coating.conductorBase = conductor;
        x.coating.thickness = thickness;
        x.coating.maxDepth = maxDepth;
        m.kind = MaterialKind::Coated;
        m.diffuse = R;
        m.reflect = Vec3(1.0f);  // (coatBaseScale)
        if (conductor) setConductorIndex(m, Vec3(0.2f, 0.5f, 1.1f) / 1.5f, Vec3(3.5f, 2.5f, 1.8f) / 1.5f);
        setCoatBaseAlphas(m, baseAlpha, baseAlpha);
        m.eta = 1.5f;
        m.alphaX = m.alphaY = coatAlpha;
        m.x = &x;
    }
};

struct Mean {
    double sum = 0, sumSq = 0;
    int n = 0;
    void add(double v) {
        sum += v;
        sumSq += v * v;
        ++n;
    }
    double mean() const { return sum / n; }
    double se() const { return std::sqrt(std::max(0.0, sumSq / n - mean() * mean()) / n); }
};

// Albedo at wo of channel c by sampling and by integrating f, N each.
void albedos(const BsdfParams& m, Vec3 wo, int N, Mean& bySampling, Mean& byF, int c = 0) {
    std::mt19937 g(7);
    std::uniform_real_distribution<float> U(0.0f, 1.0f);
    for (int i = 0; i < N; ++i) {
        BsdfSample s;
        const float a = U(g), b = U(g), d = U(g);
        bySampling.add(coatedSample(m, wo, a, b, d, TransportMode::Radiance, s) ? s.f[c] * std::fabs(s.wi.z) / s.pdf : 0.0);
        const float z = U(g), phi = 2 * kPi * U(g), r = std::sqrt(1 - z * z);
        const Vec3 wi(r * std::cos(phi), r * std::sin(phi), z);
        byF.add(coatedF(m, wo, wi)[c] * z * 2 * kPi);
    }
}

// fn(what, coat, channel) for each of four rough configurations (the Coat is built in place:
// its params point at its own extra).
template <class F>
void forEachRoughCoat(F fn) {
    struct Case {
        const char* what;
        Coat coat;
        int c;
    };
    Case cases[] = {
        {"rough coat, white diffuse", Coat(false, 0.3f, 0, 0.01f), 0},
        {"rough coat, grey diffuse, thin", Coat(false, 0.2f, 0, 1e-4f, Vec3(0.5f)), 0},
        {"rough coat, rough conductor (red)", Coat(true, 0.14f, 0.05f, 0.01f), 0},
        {"rough coat, rough conductor (blue)", Coat(true, 0.3f, 0.3f, 0.01f), 2},
    };
    for (Case& k : cases) fn(k.what, k.coat, k.c);
}

}  // namespace

TEST_CASE("Coated: sampling and f estimate one BSDF (rough coats, diffuse and conductor bases)", "[bsdf][coated]") {
    const Vec3 wo = normalize(Vec3(0.6f, 0.1f, 0.8f));
    forEachRoughCoat([&](const char* what, Coat& coat, int c) {
        Mean s, f;
        albedos(coat.m, wo, 300000, s, f, c);
        INFO(what << ": by sampling " << s.mean() << " +- " << s.se() << ", by f " << f.mean() << " +- " << f.se());
        CHECK(std::fabs(s.mean() - f.mean()) < 4.5 * std::sqrt(s.se() * s.se() + f.se() * f.se()));
    });
}

TEST_CASE("Coated: pbrt-v4's exit weighting makes f integrate above the walk's albedo", "[bsdf][coated]") {
    // MaterialDesc::Coating::pbrtExitWeight: the density pbrt-v4's LayeredBxDF weighs a
    // direction sampled inside the slab with (the exit's density of wi given it) is not the
    // density of the strategy it competes with, so the MIS weights do not sum to 1 and f is
    // biased; sampling (a plain walk) is not affected. Every rough case above then fails.
    const Vec3 wo = normalize(Vec3(0.6f, 0.1f, 0.8f));
    forEachRoughCoat([&](const char* what, Coat& coat, int c) {
        coat.x.coating.pbrtExitWeight = true;
        Mean s, f;
        albedos(coat.m, wo, 300000, s, f, c);
        INFO(what << ": by sampling " << s.mean() << " +- " << s.se() << ", by f " << f.mean() << " +- " << f.se());
        CHECK(f.mean() - s.mean() > 6 * std::sqrt(s.se() * s.se() + f.se() * f.se()));
    });
}

TEST_CASE("Coated: f is reciprocal, and pbrt-v4's exit weighting makes it depend on which side the walk starts", "[bsdf][coated]") {
    // f(a, b) = f(b, a) for a dielectric coat (its 1 / eta^2 on the way in and out cancel).
    // pbrt-v4's weighting breaks that, and pbrt evaluates a light subpath's vertex from the
    // light's side (its f(wo = light side, wi = camera side)): light tracing onto a coat
    // sees another BSDF than next-event estimation from it. On the caustic glass's floor
    // (this coat: alpha sqrt(0.0104), a 0.64 grey base) the caustic, which only pbrt's
    // light-tracing strategy reaches, is 4-8% below what f from the camera's side gives
    // (bench/bench_pbrt_blocks.cpp, docs/pbrt.md). Paired differences over directions
    // jittered by 0.01 about each pair, within 4.5 standard errors of 0 for wavemmlt's
    // weighting and beyond 6 of them for pbrt's, where it matters (a grazing light).
    Coat coat(false, std::sqrt(0.0104f), 0, 0.01f, Vec3(0.64f));
    struct Pair {
        float cosLight, cosCamera;
        bool pbrtDiffers;
    };
    for (const Pair p : {Pair{0.15f, 0.9f, true}, Pair{0.9f, 0.2f, true}, Pair{0.6f, 0.5f, false}}) {
        for (const bool pbrt : {false, true}) {
            if (pbrt && !p.pbrtDiffers) continue;
            coat.x.coating.pbrtExitWeight = pbrt;
            std::mt19937 g(5);
            std::uniform_real_distribution<float> U(-0.01f, 0.01f);
            const float sl = std::sqrt(1 - p.cosLight * p.cosLight), sc = std::sqrt(1 - p.cosCamera * p.cosCamera);
            Mean d, f;
            for (int i = 0; i < 40000; ++i) {
                const Vec3 wl = normalize(Vec3(sl + U(g), U(g), p.cosLight)), wc = normalize(Vec3(-0.3f * sc + U(g), 0.95f * sc + U(g), p.cosCamera));
                const float fc = coatedF(coat.m, wc, wl).x, fl = coatedF(coat.m, wl, wc).x;
                d.add(fc - fl);
                f.add(fc);
            }
            INFO("cos light " << p.cosLight << ", cos camera " << p.cosCamera << (pbrt ? ", pbrt's weighting" : "") << ": f " << f.mean()
                              << ", f(camera, light) - f(light, camera) " << d.mean() << " +- " << d.se());
            if (pbrt) CHECK(std::fabs(d.mean()) > 6 * d.se());
            else CHECK(std::fabs(d.mean()) < 4.5 * d.se());
        }
    }
    // The planted evaluation from the light's side (pbrtWalkFromLight) is that f turned round.
    coat.x.coating.pbrtExitWeight = true;
    const Vec3 wc = normalize(Vec3(-0.2f, 0.3f, 0.9f)), wl = normalize(Vec3(0.9f, 0.1f, 0.15f));
    const Vec3 fromLight = coatedF(coat.m, wl, wc, TransportMode::Importance);
    coat.x.coating.pbrtWalkFromLight = true;
    CHECK(coatedF(coat.m, wc, wl).x == fromLight.x);
}

TEST_CASE("Coated: a lossless slab conserves energy", "[bsdf][coated]") {
    // A smooth coat (no microfacet losses) over a white diffuse base, a slab too thin to
    // absorb, walks long enough: every path leaves, albedo 1.
    const Coat coat(false, 0.0f, 0, 1e-7f, Vec3(1.0f), 1000);
    for (float cosO : {0.9f, 0.5f, 0.15f}) {
        const Vec3 wo(std::sqrt(1 - cosO * cosO), 0, cosO);
        Mean s;
        std::mt19937 g(3);
        std::uniform_real_distribution<float> U(0.0f, 1.0f);
        for (int i = 0; i < 200000; ++i) {
            BsdfSample b;
            const float a = U(g), c = U(g), d = U(g);
            s.add(coatedSample(coat.m, wo, a, c, d, TransportMode::Radiance, b) ? b.f.x * std::fabs(b.wi.z) / b.pdf : 0.0);
        }
        INFO("cos " << cosO << ": albedo " << s.mean() << " +- " << s.se());
        CHECK(std::fabs(s.mean() - 1.0) < 4.5 * s.se() + 1e-3);
    }
}

TEST_CASE("Coated: deterministic, two-sided, a smooth coat's mirror is a delta sample", "[bsdf][coated]") {
    const Coat coat(true, 0.2f, 0.1f, 0.01f);
    const Vec3 wo = normalize(Vec3(0.3f, -0.4f, 0.8f)), wi = normalize(Vec3(-0.5f, 0.2f, 0.7f));
    const Vec3 f1 = coatedF(coat.m, wo, wi), f2 = coatedF(coat.m, wo, wi);
    CHECK(f1.x == f2.x);
    CHECK(coatedPdf(coat.m, wo, wi) == coatedPdf(coat.m, wo, wi));
    const Vec3 fb = coatedF(coat.m, -wo, -wi);
    CHECK(fb.x == f1.x);  // two-sided: the same walk from below
    CHECK(fb.z == f1.z);
    BsdfSample a, b;
    REQUIRE(coatedSample(coat.m, wo, 0.7f, 0.3f, 0.6f, TransportMode::Radiance, a));
    REQUIRE(coatedSample(coat.m, wo, 0.7f, 0.3f, 0.6f, TransportMode::Radiance, b));
    CHECK(a.wi.x == b.wi.x);
    CHECK(a.f.y == b.f.y);
    CHECK(a.pdf == b.pdf);
    CHECK(a.pdf == coatedPdf(coat.m, wo, a.wi));  // MIS reads the pdf estimate
    // a smooth coat: a small uLobe takes its mirror reflection, a delta with weight 1
    const Coat smooth(false, 0.0f, 0, 0.01f);
    BsdfSample m;
    REQUIRE(coatedSample(smooth.m, wo, 0.001f, 0.5f, 0.5f, TransportMode::Radiance, m));
    CHECK(m.delta);
    CHECK(m.wi.z == Approx(wo.z));
    CHECK(m.f.x * std::fabs(m.wi.z) / m.pdf == Approx(1.0f));
}

TEST_CASE("DiffuseTransmission: the sample's density, f and pdf", "[bsdf]") {
    BsdfParams m;
    m.kind = MaterialKind::DiffuseTransmission;
    m.diffuse = Vec3(0.3f, 0.2f, 0.1f);
    m.refract = Vec3(0.6f, 0.5f, 0.4f);
    const Vec3 wo = normalize(Vec3(0.2f, 0.3f, -0.9f));
    std::mt19937 g(5);
    std::uniform_real_distribution<float> U(0.0f, 1.0f);
    Mean integral, through;
    for (int i = 0; i < 200000; ++i) {
        const Vec3 w = sampleUniformSphere(U(g), U(g));
        integral.add(diffuseTransmissionPdf(m, wo, w) / kUniformSpherePdf);
        BsdfSample s;
        const float a = U(g), b = U(g), c = U(g);
        REQUIRE(diffuseTransmissionSample(m, wo, a, b, c, s));
        CHECK(s.pdf == Approx(diffuseTransmissionPdf(m, wo, s.wi)));
        CHECK(s.f.x == Approx(diffuseTransmissionF(m, wo, s.wi).x));
        through.add(s.wi.z * wo.z < 0 ? 1.0 : 0.0);
    }
    CHECK(std::fabs(integral.mean() - 1.0) < 4.5 * integral.se());
    CHECK(std::fabs(through.mean() - 0.6 / 0.9) < 4.5 * through.se());           // max(T) / (max(R) + max(T))
    CHECK(diffuseTransmissionF(m, wo, Vec3(0, 0, 1)).y == Approx(0.5f / kPi));   // the other side: T / pi
    CHECK(diffuseTransmissionF(m, wo, Vec3(0, 0, -1)).y == Approx(0.2f / kPi));  // wo's side: R / pi
}
