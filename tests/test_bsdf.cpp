// BSDF kernels: energy conservation, reciprocity, pdf normalisation, sampling vs pdf
// (chi-square), delta lobes (mirror, Fresnel, Snell, transport-mode scaling).
#include <catch2/catch.hpp>

#include <vector>

#include <random>

#include <cstring>

#include "chi2.h"
#include "kernels/bsdf.h"
#include "kernels/fresnel.h"
#include "kernels/scatter.h"

using namespace wmlt;
using chi2::dirAt;
using chi2::kDeg;

namespace {
constexpr double kMinP = 1e-3;

bool close(double a, double b, double rel = 1e-6) { return std::fabs(a - b) <= rel * std::max(std::fabs(a), std::fabs(b)); }
BsdfParams matte(Vec3 kd) {
    BsdfParams m;
    m.kind = MaterialKind::Matte;
    m.diffuse = kd;
    return m;
}
BsdfParams glossy(Vec3 kd, Vec3 ks, float n) {
    BsdfParams m;
    m.kind = MaterialKind::Glossy;
    m.diffuse = kd;
    m.specular = ks;
    m.shininess = n;
    return m;
}
BsdfParams mirror(Vec3 r) {
    BsdfParams m;
    m.kind = MaterialKind::Reflective;
    m.reflect = r;
    return m;
}
BsdfParams glass(float eta, Vec3 r = Vec3(1.0f), Vec3 t = Vec3(1.0f)) {
    BsdfParams m;
    m.kind = MaterialKind::Dielectric;
    m.eta = eta;
    m.reflect = r;
    m.refract = t;
    return m;
}
// Probability of the Phong lobe in the Glossy mixture.
double phongProb(const BsdfParams& m) {
    double ld = luminance(m.diffuse), ls = luminance(m.specular);
    return ls / (ld + ls);
}

// Mass of the power-cosine lobe (exponent n) about the mirror direction that falls below
// the horizon, for |cos theta_o| = cosR. With t = cos^(n+1)(theta) uniform on [0, 1] (the
// lobe's CDF) and the fraction of azimuths below the horizon acos(cot theta cot theta_r)/pi:
//   lost = int_0^{sin^(n+1) theta_r} acos(cos theta cos theta_r / (sin theta sin theta_r)) / pi dt.
double phongLostMass(double n, double cosR) {
    double sinR = std::sqrt(std::max(0.0, 1 - cosR * cosR)), tk = std::pow(sinR, n + 1);
    if (tk <= 0) return 0;
    auto frac = [&](double t) {
        double c = std::pow(t, 1 / (n + 1)), s = std::sqrt(std::max(0.0, 1 - c * c));
        double a = c * cosR, b = s * sinR;
        return a >= b ? 0.0 : std::acos(a / b) / M_PI;
    };
    return chi2::adaptiveSimpson(frac, 0, tk, 1e-11, 30, 16);
}

// Directional albedo rho(wo) = E[f |cos wi| / pdf] per channel, with its standard error;
// failed samples contribute 0. Also checks that each sample's weight is finite.
struct Albedo {
    double mean[3] = {0, 0, 0}, se[3] = {0, 0, 0};
    bool finite = true;
};
Albedo albedo(const BsdfParams& m, Vec3 wo, TransportMode mode, int N, uint64_t seed) {
    chi2::Pcg32 g(seed);
    double s[3] = {0, 0, 0}, s2[3] = {0, 0, 0};
    Albedo a;
    for (int i = 0; i < N; ++i) {
        float ul = g.uniform(), u1 = g.uniform(), u2 = g.uniform();
        BsdfSample bs;
        if (!bsdfSample(m, wo, ul, u1, u2, mode, bs)) continue;
        Vec3 w = bs.f * (absCosTheta(bs.wi) / bs.pdf);
        a.finite = a.finite && isFinite(w) && bs.pdf > 0;
        for (int c = 0; c < 3; ++c) {
            s[c] += w[c];
            s2[c] += double(w[c]) * w[c];
        }
    }
    for (int c = 0; c < 3; ++c) {
        a.mean[c] = s[c] / N;
        a.se[c] = std::sqrt(std::max(0.0, s2[c] / N - a.mean[c] * a.mean[c]) / N);
    }
    return a;
}

std::vector<BsdfParams> glossyCases() {
    return {glossy(Vec3(0.5f), Vec3(0.5f), 0),    glossy(Vec3(0.3f), Vec3(0.7f), 1),
            glossy(Vec3(0.2f), Vec3(0.8f), 10),   glossy(Vec3(0.1f), Vec3(0.9f), 100),
            glossy(Vec3(0.0f), Vec3(1.0f), 1e4f), glossy(Vec3(0.5f), Vec3(0.5f), 1e4f),
            glossy(Vec3(0.0f), Vec3(1.0f), 1e5f), glossy(Vec3(0.7f, 0.2f, 0.1f), Vec3(0.3f, 0.8f, 0.9f), 30)};
}
const double kThetas[] = {0, 30, 60, 80, 89, 89.9, 180, 150, 100, 90.5};  // > 90: wo below
}  // namespace

TEST_CASE("albedo <= 1 for all materials and directions", "[bsdf][energy]") {
    std::vector<BsdfParams> ms = glossyCases();
    ms.push_back(matte(Vec3(1.0f)));
    ms.push_back(matte(Vec3(0.8f, 0.5f, 0.2f)));
    ms.push_back(mirror(Vec3(1.0f)));
    for (float eta : {1.0001f, 1.5f, 4.0f}) {
        ms.push_back(glass(eta));
        ms.push_back(glass(1 / eta));
    }
    int k = 0;
    for (const BsdfParams& m : ms)
        for (double th : kThetas) {
            Vec3 wo = dirAt(th, 37);
            Albedo a = albedo(m, wo, TransportMode::Importance, 100000, 100 + k++);
            INFO("kind " << int(m.kind) << " n " << m.shininess << " eta " << m.eta << " theta " << th);
            CHECK(a.finite);
            // 5 standard errors of MC noise, 1e-5 for float rounding of weights equal to 1.
            for (int c = 0; c < 3; ++c) CHECK(a.mean[c] <= 1 + 5 * a.se[c] + 1e-5);
            if (m.kind == MaterialKind::Matte)
                for (int c = 0; c < 3; ++c) CHECK(a.mean[c] == Approx(m.diffuse[c]).epsilon(1e-5));
            if (m.kind == MaterialKind::Reflective || m.kind == MaterialKind::Dielectric)
                for (int c = 0; c < 3; ++c) CHECK(a.mean[c] == Approx(1.0).epsilon(1e-5));  // F + T = 1
            // Normalised Phong: albedo exactly Kd + Ks at normal incidence (no lobe lost).
            if (m.kind == MaterialKind::Glossy && (th == 0 || th == 180))
                for (int c = 0; c < 3; ++c) CHECK(std::fabs(a.mean[c] - (m.diffuse[c] + m.specular[c])) <= 5 * a.se[c] + 1e-5);
        }
}

// Reference albedo of the spec's Glossy formula, in double (the float f of a sharp lobe has
// relative rounding noise ~ n * 2^-24 from cos a): quadrature about the mirror direction.
double glossyAlbedoRef(const BsdfParams& m, Vec3 wo) {
    double n = m.shininess, kd = luminance(m.diffuse), ks = luminance(m.specular);
    double r[3] = {-wo.x, -wo.y, wo.z}, a[3] = {0, 0, 1};
    if (std::fabs(r[2]) > 0.9) {
        a[0] = 1;
        a[2] = 0;
    }
    double s[3] = {a[1] * r[2] - a[2] * r[1], a[2] * r[0] - a[0] * r[2], a[0] * r[1] - a[1] * r[0]};
    double sl = std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
    for (double& x : s) x /= sl;
    double t[3] = {r[1] * s[2] - r[2] * s[1], r[2] * s[0] - r[0] * s[2], r[0] * s[1] - r[1] * s[0]};
    auto g = [&](double th, double ph) {
        double ct = std::cos(th), st = std::sin(th);
        double z = r[2] * ct + st * (std::cos(ph) * s[2] + std::sin(ph) * t[2]);
        if (z * wo.z <= 0) return 0.0;
        double f = kd / M_PI + (ct > 0 ? ks * (n + 2) / (2 * M_PI) * std::pow(ct, n) : 0.0);
        return f * std::fabs(z) * st;
    };
    auto bins = chi2::SphereBins::lobe(Vec3(0, 0, 1), n, 10, 4, 8);
    double sum = 0;
    for (size_t i = 0; i + 1 < bins.thetaEdges.size(); ++i)
        for (int j = 0; j < 8; ++j)
            sum += chi2::adaptiveSimpson2D(g, bins.thetaEdges[i], bins.thetaEdges[i + 1], j * M_PI / 4, (j + 1) * M_PI / 4, 1e-9, 12);
    return sum;
}

TEST_CASE("Glossy albedo: sampling estimate equals quadrature of f cos", "[bsdf][energy]") {
    int k = 0;
    for (const BsdfParams& m : glossyCases())
        for (double th : {0.0, 45.0, 80.0, 120.0}) {
            Vec3 wo = dirAt(th, 10);
            double q = glossyAlbedoRef(m, wo);
            Albedo a = albedo(m, wo, TransportMode::Radiance, 200000, 300 + k++);
            double mc = 0.2126 * a.mean[0] + 0.7152 * a.mean[1] + 0.0722 * a.mean[2];
            double se = 0.2126 * a.se[0] + 0.7152 * a.se[1] + 0.0722 * a.se[2];
            INFO("n " << m.shininess << " theta " << th << " quad " << q << " mc " << mc << " se " << se);
            CHECK(std::fabs(mc - q) <= 5 * se + 1e-5);
        }
}

TEST_CASE("Matte and Glossy are reciprocal", "[bsdf][reciprocity]") {
    std::vector<BsdfParams> ms = glossyCases();
    ms.push_back(matte(Vec3(0.3f, 0.6f, 0.9f)));
    chi2::Pcg32 g(7);
    int bad = 0, nonzero = 0;
    for (const BsdfParams& m : ms)
        for (int i = 0; i < 20000; ++i) {
            Vec3 wo = sampleUniformSphere(g.uniform(), g.uniform()), wi = sampleUniformSphere(g.uniform(), g.uniform());
            if (i % 2) wi = normalize(Vec3(-wo.x, -wo.y, wo.z) + 0.01f * wi);  // near the lobe's peak
            Vec3 a = bsdfF(m, wo, wi), b = bsdfF(m, wi, wo);
            for (int c = 0; c < 3; ++c) bad += !(a[c] == b[c] || close(a[c], b[c]));
            nonzero += a[1] > 0;
        }
    CHECK(bad == 0);
    CHECK(nonzero > 50000);  // half of the pairs share a hemisphere
}

TEST_CASE("BSDF pdfs integrate to one over the sphere", "[bsdf][pdf]") {
    for (double th : {0.0, 50.0, 130.0}) {
        BsdfParams m = matte(Vec3(0.5f));
        Vec3 wo = dirAt(th, 0);
        double s = 0;
        for (double v : chi2::SphereBins::uniform({0, 0, 1}, 10, 8).integrate([&](Vec3 w) { return bsdfPdf(m, wo, w); })) s += v;
        CHECK(s == Approx(1.0).margin(1e-6));
    }
    for (const BsdfParams& m : glossyCases()) {
        for (double th : {0.0, 30.0, 70.0, 85.0, 89.0, 160.0}) {
            Vec3 wo = dirAt(th, 25), r(-wo.x, -wo.y, wo.z), e = cross(Vec3(0, 0, 1), r);
            // Bins about the lobe's axis; for n <= 1 (lobe with an edge or a kink) about the
            // axis e where the horizon and the lobe's edge meet, so both are meridians there.
            auto bins = m.shininess > 1 ? chi2::SphereBins::lobe(r, m.shininess, 10, 4, 8)
                                        : chi2::SphereBins::uniform(length(e) > 1e-3f ? normalize(e) : Vec3(0, 0, 1), 10, 16);
            double s = 0;
            // (depth 14: the jumps across meridians are resolved to 1e-5 of a bin's width)
            for (double v : bins.integrate([&](Vec3 w) { return glossyPdf(m, wo, w); }, 1e-8, m.shininess > 1 ? 8 : 14)) s += v;
            double lost = phongProb(m) * phongLostMass(m.shininess, std::fabs(wo.z));
            INFO("n " << m.shininess << " theta " << th << " integral " << s << " lost " << lost);
            CHECK(s == Approx(1.0 - lost).margin(1e-5));  // quadrature error
            CHECK(s <= 1 + 1e-5);
            if (th == 0.0) CHECK(lost == 0.0);
        }
    }
}

TEST_CASE("Matte sampling matches its pdf (chi-square)", "[bsdf][chi2]") {
    BsdfParams m = matte(Vec3(0.5f));
    int k = 0, mismatches = 0;
    for (double th : {0.0, 70.0, 120.0}) {
        Vec3 wo = dirAt(th, 30);
        auto sample = [&](chi2::Pcg32& g, Vec3& w) {
            BsdfSample s;
            float ul = g.uniform(), u1 = g.uniform(), u2 = g.uniform();
            if (!bsdfSample(m, wo, ul, u1, u2, TransportMode::Radiance, s)) return false;
            // the sample's f and pdf are those of bsdfF and bsdfPdf
            mismatches += !close(s.f[0], bsdfF(m, wo, s.wi)[0]) || !close(s.pdf, bsdfPdf(m, wo, s.wi));
            w = s.wi;
            return true;
        };
        auto r = chi2::sphereTest(
            sample, [&](Vec3 w) { return bsdfPdf(m, wo, w); }, chi2::SphereBins::uniform({0, 0, 1}, 10, 20), 400000, 0, 500 + k++);
        INFO("theta " << th << " " << chi2::describe(r));
        CHECK(r.pValue > kMinP);
    }
    CHECK(mismatches == 0);
}

TEST_CASE("Glossy sampling matches its pdf (chi-square)", "[bsdf][chi2]") {
    int k = 0, mismatches = 0;
    for (const BsdfParams& m : glossyCases()) {
        for (double th : {0.0, 40.0, 75.0, 88.0, 135.0}) {
            Vec3 wo = dirAt(th, 200), axis(-wo.x, -wo.y, wo.z);
            auto sample = [&](chi2::Pcg32& g, Vec3& w) {
                BsdfSample s;
                float ul = g.uniform(), u1 = g.uniform(), u2 = g.uniform();
                if (!bsdfSample(m, wo, ul, u1, u2, TransportMode::Radiance, s)) return false;
                Vec3 f = bsdfF(m, wo, s.wi);
                for (int c = 0; c < 3; ++c) mismatches += !close(s.f[c], f[c]);
                mismatches += !close(s.pdf, bsdfPdf(m, wo, s.wi)) || s.delta;
                w = s.wi;
                return true;
            };
            // Rejected (below-horizon) samples form the extra bin with mass ps * lost.
            double missing = phongProb(m) * phongLostMass(m.shininess, std::fabs(wo.z));
            auto r = chi2::sphereTest(
                sample, [&](Vec3 w) { return bsdfPdf(m, wo, w); }, chi2::SphereBins::lobe(axis, m.shininess, 10, 4, 20), 300000, missing, 600 + k++);
            INFO("n " << m.shininess << " theta " << th << " missing " << missing << " " << chi2::describe(r));
            CHECK(r.pValue > kMinP);
        }
    }
    CHECK(mismatches == 0);
}

TEST_CASE("Glossy is robust at extreme exponents and grazing angles", "[bsdf]") {
    const float us[] = {0.0f, 1e-7f, 0.5f, 1.0f - 0x1p-24f};
    for (float n : {0.0f, 1.0f, 1e5f, 1e6f})
        for (float z : {1.0f, 0.5f, 1e-3f, 1e-6f, -1e-6f, -0.7f}) {
            BsdfParams m = glossy(Vec3(0.2f), Vec3(0.8f), n);
            Vec3 wo = normalize(Vec3(std::sqrt(1 - z * z), 0.0f, z));
            for (float ul : us)
                for (float u1 : us)
                    for (float u2 : us) {
                        BsdfSample s;
                        if (!glossySample(m, wo, ul, u1, u2, s)) continue;
                        INFO("n " << n << " z " << z << " u " << ul << " " << u1 << " " << u2);
                        REQUIRE(isFinite(s.f));
                        REQUIRE(std::isfinite(s.pdf));
                        REQUIRE(s.pdf > 0);
                        REQUIRE(sameHemisphere(wo, s.wi));
                    }
            REQUIRE(isFinite(glossyF(m, wo, Vec3(-wo.x, -wo.y, wo.z))));
        }
    BsdfSample s;
    CHECK_FALSE(glossySample(glossy(Vec3(0.0f), Vec3(0.0f), 10), Vec3(0, 0, 1), 0.5f, 0.5f, 0.5f, s));
    // u1 = 0 maps to the disk's rim: a grazing direction of pdf 0, rejected, not NaN.
    if (bsdfSample(matte(Vec3(0.5f)), Vec3(0, 0, 1), 0.5f, 0.0f, 0.5f, TransportMode::Radiance, s)) CHECK((s.pdf > 0 && isFinite(s.f)));
}

// ---- Delta lobes --------------------------------------------------------------------

TEST_CASE("Reflective: exact mirror direction, weight = Reflect, two-sided", "[bsdf][delta]") {
    BsdfParams m = mirror(Vec3(0.9f, 0.5f, 0.1f));
    for (double th : {0.0, 33.0, 89.9, 120.0, 179.0}) {
        Vec3 wo = dirAt(th, 77);
        BsdfSample s;
        REQUIRE(bsdfSample(m, wo, 0.3f, 0.1f, 0.2f, TransportMode::Radiance, s));
        CHECK(s.delta);
        CHECK(s.pdf == 1.0f);
        CHECK((s.wi.x == -wo.x && s.wi.y == -wo.y && s.wi.z == wo.z));
        Vec3 w = s.f * absCosTheta(s.wi);
        for (int c = 0; c < 3; ++c) CHECK(w[c] == Approx(m.reflect[c]).epsilon(1e-6));
        CHECK(isBlack(bsdfF(m, wo, s.wi)));  // delta lobes are never evaluated
        CHECK(bsdfPdf(m, wo, s.wi) == 0.0f);
    }
}

// Independent form of the Fresnel equations (Hecht): R_s = sin^2(i-t)/sin^2(i+t),
// R_p = tan^2(i-t)/tan^2(i+t), in double.
static double fresnelHecht(double cosI, double etaRel) {
    double ti = std::acos(cosI), st = std::sin(ti) / etaRel;
    if (st >= 1) return 1;
    double tt = std::asin(st);
    if (ti == 0) {
        double r = (etaRel - 1) / (etaRel + 1);
        return r * r;
    }
    double rs = std::sin(ti - tt) / std::sin(ti + tt), rp = std::tan(ti - tt) / std::tan(ti + tt);
    return 0.5 * (rs * rs + rp * rp);
}

TEST_CASE("Fresnel: normal incidence, both sides, TIR, Hecht's form, Schlick", "[bsdf][fresnel]") {
    for (float eta : {1.0001f, 1.33f, 1.5f, 2.4f, 4.0f, 0.5f}) {
        INFO("eta " << eta);
        double r0 = double(eta - 1) * (eta - 1) / (double(eta + 1) * (eta + 1));
        CHECK(fresnelDielectric(1.0f, eta) == Approx(r0).epsilon(1e-5).margin(1e-9));
        CHECK(fresnelDielectric(-1.0f, eta) == Approx(r0).epsilon(1e-5).margin(1e-9));
        CHECK(fresnelSchlick(1.0f, eta) == Approx(r0).epsilon(1e-5).margin(1e-9));
        CHECK(fresnelDielectric(0.0f, eta) == Approx(1.0f));
        for (int i = 1; i <= 200; ++i) {
            float c = i / 200.0f;  // the same cosine from outside, then from inside
            CHECK(fresnelDielectric(c, eta) == Approx(fresnelHecht(c, eta)).margin(2e-6));
            CHECK(fresnelDielectric(-c, eta) == Approx(fresnelHecht(c, 1.0 / eta)).margin(2e-6));
            float fs = fresnelSchlick(c, eta);
            CHECK((fs >= 0 && fs <= 1 && fs <= fresnelSchlick(c - 0.005f, eta) + 1e-7f));
            // Symmetry: F is the same for the ray travelling backwards. Start from the
            // denser side (its angle is the ill-conditioned one near the critical angle)
            // and get the corresponding angle on the other side in double.
            float cd = eta > 1 ? -c : c;  // the direction in the denser medium
            double etaRel = eta > 1 ? 1.0 / eta : eta, cos2 = 1 - (1 - double(c) * c) / (etaRel * etaRel);
            if (cos2 <= 0) {
                CHECK(fresnelDielectric(cd, eta) == 1.0f);
                continue;
            }
            float co = float(eta > 1 ? std::sqrt(cos2) : -std::sqrt(cos2));  // in the rarer medium
            CHECK(fresnelDielectric(cd, eta) == Approx(fresnelHecht(std::sqrt(cos2), 1 / etaRel)).margin(2e-6));
            CHECK(fresnelDielectric(cd, eta) == Approx(fresnelDielectric(co, eta)).margin(2e-6));
            CHECK(fresnelSchlick(cd, eta) == Approx(fresnelSchlick(co, eta)).margin(2e-6));
        }
    }
    // Total internal reflection from inside glass beyond asin(1/1.5) = 41.81 degrees.
    double crit = std::asin(1 / 1.5) / kDeg;
    CHECK(fresnelDielectric(-float(std::cos((crit + 0.01) * kDeg)), 1.5f) == 1.0f);
    CHECK(fresnelDielectric(-float(std::cos((crit - 0.01) * kDeg)), 1.5f) < 1.0f);
    CHECK(fresnelSchlick(-float(std::cos((crit + 0.01) * kDeg)), 1.5f) == 1.0f);
    CHECK(fresnelDielectric(float(std::cos(89.0 * kDeg)), 1.5f) < 1.0f);  // never TIR from outside
}

TEST_CASE("Dielectric: Snell's law, reflection probability = F, TIR", "[bsdf][delta]") {
    int k = 0;
    for (float eta : {1.0001f, 1.5f, 4.0f})
        for (double th : {0.0, 20.0, 41.0, 43.0, 60.0, 85.0, 180.0, 160.0, 139.0, 137.0, 100.0}) {
            BsdfParams m = glass(eta);
            Vec3 wo = dirAt(th, 130);
            bool outside = wo.z > 0;
            double nO = outside ? 1 : eta, nI = outside ? eta : 1;  // wo's and the refracted side
            double F = fresnelDielectric(wo.z, eta);
            INFO("eta " << eta << " theta " << th << " F " << F);
            const int N = 20000;
            chi2::Pcg32 g(900 + k++);
            int nRefl = 0, bad = 0;
            for (int i = 0; i < N; ++i) {
                BsdfSample s;
                bad += !dielectricSample(m, wo, g.uniform(), TransportMode::Importance, s) || !s.delta || std::fabs(length(s.wi) - 1) > 1e-6f;
                if (s.wi.z * wo.z > 0) {  // reflection: exact mirror, pdf F
                    ++nRefl;
                    bad += s.wi.x != -wo.x || s.wi.y != -wo.y || s.wi.z != wo.z || !close(s.pdf, F);
                } else {  // refraction: n_o sin_o = n_i sin_i, opposite azimuth, pdf 1 - F
                    double sinO = std::sqrt(double(wo.x) * wo.x + double(wo.y) * wo.y);
                    double sinI = std::sqrt(double(s.wi.x) * s.wi.x + double(s.wi.y) * s.wi.y);
                    bad += std::fabs(nO * sinO - nI * sinI) > 1e-6 || wo.x * s.wi.x + wo.y * s.wi.y > 0 || !close(s.pdf, 1 - F, 1e-5);
                }
            }
            CHECK(bad == 0);
            // Binomial: fraction of reflections = F within 5 standard errors.
            CHECK(std::fabs(double(nRefl) / N - F) <= 5 * std::sqrt(F * (1 - F) / N) + 1e-9);
            double sinCrit = 1 / eta;  // only from inside (wo.z < 0)
            if (!outside && std::sqrt(1 - double(wo.z) * wo.z) > sinCrit + 1e-6) CHECK(nRefl == N);
        }
}

TEST_CASE("Dielectric: lobe colours, Radiance vs Importance scaling", "[bsdf][delta]") {
    const Vec3 R(0.2f, 0.5f, 1.0f), T(1.0f, 0.3f, 0.1f);
    for (float eta : {1.0001f, 1.5f, 4.0f})
        for (double th : {10.0, 60.0, 170.0, 120.0}) {
            BsdfParams m = glass(eta, R, T);
            Vec3 wo = dirAt(th, 45);
            double F = fresnelDielectric(wo.z, eta);
            float etaRel = wo.z > 0 ? eta : 1 / eta;  // n(wi's medium) / n(wo's medium) on refraction
            INFO("eta " << eta << " theta " << th);
            for (float ul : {0.0f, float(F) * 0.5f, float(F) + 1e-3f, 0.999f}) {
                BsdfSample si, sr;
                if (!dielectricSample(m, wo, ul, TransportMode::Importance, si)) continue;
                REQUIRE(dielectricSample(m, wo, ul, TransportMode::Radiance, sr));
                REQUIRE((si.wi.x == sr.wi.x && si.wi.y == sr.wi.y && si.wi.z == sr.wi.z));
                REQUIRE(si.pdf == sr.pdf);
                bool refl = si.wi.z * wo.z > 0;
                Vec3 w = si.f * (absCosTheta(si.wi) / si.pdf);  // lobe weight = its colour
                for (int c = 0; c < 3; ++c) {
                    CHECK(w[c] == Approx(refl ? R[c] : T[c]).epsilon(1e-5));
                    CHECK(sr.f[c] == Approx(si.f[c] * (refl ? 1.0f : 1 / (etaRel * etaRel))).epsilon(1e-6));
                }
            }
        }
    // Round trip through a slab in Radiance mode: in (1/eta^2) and out (eta^2) cancel,
    // leaving T_in * T_out = (1 - F)^2 (Fresnel symmetric).
    BsdfParams m = glass(1.5f);
    Vec3 wo = dirAt(35, 0);
    BsdfSample in, out;
    REQUIRE(dielectricSample(m, wo, 0.999f, TransportMode::Radiance, in));
    // The slab's far face, in its own frame (normal flipped): the ray arrives from inside.
    REQUIRE(dielectricSample(m, Vec3(-in.wi.x, -in.wi.y, in.wi.z), 0.999f, TransportMode::Radiance, out));
    double F = fresnelDielectric(wo.z, 1.5f);
    CHECK(out.wi.z == Approx(wo.z).epsilon(1e-6));
    CHECK(in.f[0] * absCosTheta(in.wi) / in.pdf * out.f[0] * absCosTheta(out.wi) / out.pdf == Approx(1.0).epsilon(1e-5));
    CHECK(in.f[0] * absCosTheta(in.wi) * out.f[0] * absCosTheta(out.wi) == Approx((1 - F) * (1 - F)).epsilon(1e-5));
}

// PT's flat loop for matte bounces (matteScatter) must make what the per-hit code makes,
// bit for bit: the frame from the shading normal, matteSampleFrom on the cosine-weighted
// direction (flipped to wo's side), beta f |cos| / pdf, Russian roulette (survivesRoulette,
// scale 1) and normalize(toWorld(wi)); for wo on either side, black Kd channels and
// numbers that kill paths.
TEST_CASE("matteScatter equals the per-hit matte bounce bit for bit", "[bsdf]") {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u01(0.0f, 1.0f), sgn(-1.0f, 1.0f);
    auto unit = [&] {
        wmlt::Vec3 v;
        do v = wmlt::Vec3(sgn(rng), sgn(rng), sgn(rng));
        while (!(wmlt::lengthSquared(v) > 0.01f && wmlt::lengthSquared(v) < 1.0f));
        return wmlt::normalize(v);
    };
    const size_t n = 2039;
    std::vector<float> ns(3 * n), wo(3 * n), lx(n), ly(n), lz(n), kd(3 * n), beta(3 * n), u(n);
    for (size_t h = 0; h < n; ++h) {
        const wmlt::Vec3 N = h % 17 == 0 ? wmlt::Vec3(0.0f, 0.0f, h % 2 ? 1.0f : -1.0f) : unit(), O = unit();
        float x, y, z;
        wmlt::sampleCosineHemisphere(u01(rng), u01(rng), x, y, z);
        lx[h] = x;
        ly[h] = y;
        lz[h] = z;
        for (int a = 0; a < 3; ++a) {
            ns[3 * h + a] = N[a];
            wo[3 * h + a] = O[a];
            kd[3 * h + a] = h % 7 == 0 ? 0.0f : (a == 1 && h % 5 == 0 ? 0.0f : u01(rng));
            beta[3 * h + a] = 0.05f + u01(rng);
        }
        u[h] = u01(rng);
    }
    auto same = [](float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; };
    for (bool roulette : {false, true}) {
        std::vector<float> nextBeta(3 * n), dir(3 * n), pdf(n);
        std::vector<uint32_t> ok(n);
        (roulette ? wmlt::matteScatter<true> : wmlt::matteScatter<false>)(n, ns.data(), wo.data(), lx.data(), ly.data(), lz.data(), kd.data(),
                                                                          beta.data(), u.data(), nextBeta.data(), dir.data(), pdf.data(), ok.data());
        size_t differ = 0, alive = 0, dead = 0;
        for (size_t h = 0; h < n; ++h) {
            const wmlt::Frame fr = wmlt::Frame::fromNormal(wmlt::Vec3(ns[3 * h], ns[3 * h + 1], ns[3 * h + 2]));
            wmlt::BsdfParams m;
            m.diffuse = wmlt::Vec3(kd[3 * h], kd[3 * h + 1], kd[3 * h + 2]);
            const wmlt::Vec3 woL = fr.toLocal(wmlt::Vec3(wo[3 * h], wo[3 * h + 1], wo[3 * h + 2]));
            wmlt::BsdfSample s;
            bool go = wmlt::matteSampleFrom(m, woL, wmlt::Vec3(lx[h], ly[h], lz[h]), s) && s.pdf > 0 && !wmlt::isBlack(s.f);
            wmlt::Vec3 b = wmlt::Vec3(beta[3 * h], beta[3 * h + 1], beta[3 * h + 2]) * s.f * (wmlt::absCosTheta(s.wi) / s.pdf);
            if (go && roulette) go = wmlt::survivesRoulette(b, 1.0f, u[h]);
            if (go != (ok[h] != 0)) {
                ++differ;
                continue;
            }
            if (!go) {
                ++dead;
                continue;
            }
            ++alive;
            const wmlt::Vec3 d = wmlt::normalize(fr.toWorld(s.wi));
            for (int a = 0; a < 3; ++a)
                if (!same(b[a], nextBeta[3 * h + a]) || !same(d[a], dir[3 * h + a])) ++differ;
            if (!same(s.pdf, pdf[h])) ++differ;
        }
        INFO("roulette " << roulette);
        CHECK(alive > n / 4);
        CHECK(dead > n / 10);
        CHECK(differ == 0);
    }
}
