// The warps of kernels/sampling.h sample their pdfs; MIS weights form partitions of unity.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <vector>

#include "chi2.h"
#include "kernels/rng.h"
#include "kernels/sampling.h"

using namespace wmlt;

namespace {
constexpr double kMinP = 1e-3;  // chi-square significance threshold (as in Mitsuba's tests)

double sphereIntegral(const chi2::SphereBins& bins, const std::function<float(Vec3)>& pdf) {
    double s = 0;
    for (double v : bins.integrate(pdf)) s += v;
    return s;
}
}  // namespace

TEST_CASE("cosine hemisphere warp samples cos/pi", "[sampling]") {
    auto pdf = [](Vec3 w) { return cosineHemispherePdf(w.z); };
    auto bins = chi2::SphereBins::uniform({0, 0, 1}, 10, 20);
    CHECK(sphereIntegral(bins, pdf) == Approx(1.0).epsilon(1e-5));
    auto r = chi2::sphereTest(
        [](chi2::Pcg32& g, Vec3& w) {
            float u1 = g.uniform(), u2 = g.uniform();
            w = sampleCosineHemisphere(u1, u2);
            return true;
        },
        pdf, bins, 500000, 0, 11);
    INFO(chi2::describe(r));
    CHECK(r.pValue > kMinP);
}

TEST_CASE("uniform sphere warp samples 1/(4 pi)", "[sampling]") {
    auto pdf = [](Vec3) { return kUniformSpherePdf; };
    auto bins = chi2::SphereBins::uniform(normalize(Vec3(0.3f, -0.5f, 0.8f)), 10, 20);
    CHECK(sphereIntegral(bins, pdf) == Approx(1.0).epsilon(1e-5));
    auto r = chi2::sphereTest(
        [](chi2::Pcg32& g, Vec3& w) {
            float u1 = g.uniform(), u2 = g.uniform();
            w = sampleUniformSphere(u1, u2);
            return std::fabs(length(w) - 1.0f) < 1e-5f;
        },
        pdf, bins, 500000, 0, 12);
    INFO(chi2::describe(r));
    CHECK(r.pValue > kMinP);
}

TEST_CASE("power cosine warp samples (n+1)/(2 pi) cos^n", "[sampling]") {
    for (float n : {0.0f, 1.0f, 10.0f, 100.0f, 1e4f, 1e5f}) {
        INFO("n = " << n);
        auto pdf = [n](Vec3 w) { return powerCosinePdf(n, w.z); };
        auto bins = chi2::SphereBins::lobe({0, 0, 1}, n, 10, 2, 16);
        CHECK(sphereIntegral(bins, pdf) == Approx(1.0).epsilon(1e-4));
        auto r = chi2::sphereTest(
            [n](chi2::Pcg32& g, Vec3& w) {
                float u1 = g.uniform(), u2 = g.uniform();
                w = samplePowerCosine(n, u1, u2);
                return isFinite(w) && std::fabs(length(w) - 1.0f) < 1e-5f;
            },
            pdf, bins, 400000, 0, 13);
        INFO(chi2::describe(r));
        CHECK(r.pValue > kMinP);

        // Moments: E[cos] = (n+1)/(n+2), E[sin^2] = 2/(n+3) (integrate (n+1) c^n dc).
        chi2::Pcg32 g(14);
        const int N = 200000;
        double sc = 0, sc2 = 0, ss = 0, ss2 = 0;
        for (int i = 0; i < N; ++i) {
            float u1 = g.uniform(), u2 = g.uniform();
            Vec3 w = samplePowerCosine(n, u1, u2);
            double c = w.z, s2 = double(w.x) * w.x + double(w.y) * w.y;
            sc += c;
            sc2 += c * c;
            ss += s2;
            ss2 += s2 * s2;
        }
        double mc = sc / N, ms = ss / N;
        double sec = std::sqrt(std::max(0.0, sc2 / N - mc * mc) / N);
        double ses = std::sqrt(std::max(0.0, ss2 / N - ms * ms) / N);
        CHECK(std::fabs(mc - (n + 1.0) / (n + 2.0)) <= 5 * sec + 1e-7);  // 1e-7: float rounding of cos
        CHECK(std::fabs(ms - 2.0 / (n + 3.0)) <= 5 * ses);
    }
}

TEST_CASE("concentric disk map is uniform on the unit disk", "[sampling]") {
    float x, y;
    sampleConcentricDisk(0.5f, 0.5f, x, y);
    CHECK((x == 0 && y == 0));
    sampleConcentricDisk(1.0f, 0.5f, x, y);
    CHECK(x == Approx(1.0f));
    CHECK(y == Approx(0.0f).margin(1e-6));
    // Histogram in (r^2, phi): equal-area cells, each with probability 1 / (nr * nphi).
    const int nr = 8, nphi = 16, N = 400000;
    std::vector<double> obs(nr * nphi, 0.0), expd(nr * nphi, double(N) / (nr * nphi));
    chi2::Pcg32 g(21);
    bool inside = true;
    for (int i = 0; i < N; ++i) {
        float u1 = g.uniform(), u2 = g.uniform();
        sampleConcentricDisk(u1, u2, x, y);
        double r2 = double(x) * x + double(y) * y, ph = std::atan2(double(y), double(x));
        inside = inside && r2 <= 1.0 + 1e-6;
        if (ph < 0) ph += 2 * M_PI;
        int ir = std::min(int(r2 * nr), nr - 1), ip = std::min(int(ph / (2 * M_PI) * nphi), nphi - 1);
        obs[ir * nphi + ip] += 1;
    }
    CHECK(inside);
    auto r = chi2::pearson(obs, expd);
    INFO(chi2::describe(r));
    CHECK(r.pValue > kMinP);
}

// sinCosQuarter and sinCos2Pi (the warps' angles, without libm) against sin and cos in
// double on a dense grid of their whole ranges (every quarter of the circle): sinCosQuarter
// within 2 ulp of the value; sinCos2Pi within 2^-23 (2 ulp at 1/2 to 1) of sin and cos of
// the exact 2 pi u (std::sin of the float 2 pi u is off by 9e-8 near u = 1/2 alone).
TEST_CASE("sinCosQuarter and sinCos2Pi are within 2 ulp of sin and cos", "[sampling]") {
    auto ulps = [](float got, double want) {
        return want == 0 ? (got == 0 ? 0.0 : 1e9) : std::fabs(double(got) - want) / std::ldexp(1.0, std::ilogb(want) - 23);
    };
    double worstQ = 0, worst2Pi = 0;
    const int n = 1 << 20;
    for (int i = 0; i <= n; ++i) {
        const float t = float(-M_PI / 4 + M_PI / 2 * double(i) / n);
        float s, c;
        sinCosQuarter(t, s, c);
        worstQ = std::max({worstQ, ulps(s, std::sin(double(t))), ulps(c, std::cos(double(t)))});
        const float u = float(i) / float(n);  // [0, 1]
        sinCos2Pi(u, s, c);
        const double phi = 2.0 * M_PI * double(u);
        worst2Pi = std::max({worst2Pi, std::fabs(s - std::sin(phi)), std::fabs(c - std::cos(phi))});
    }
    INFO("sinCosQuarter " << worstQ << " ulp, sinCos2Pi " << worst2Pi << " absolute");
    CHECK(worstQ <= 2.0);
    CHECK(worst2Pi <= 0x1p-23);
}

// The concentric map as first written (Shirley and Chiu's two branches), the reference for
// the select form the warps use: the select form must give its bits exactly (no image may
// have changed when it replaced this), on the map's special inputs (the centre, the axes,
// the diagonals, the corners) and on a grid; and the flat loop of the scatter stages must
// give the per-hit warp's bits on 2^16 keys.
namespace {
void concentricDiskBranches(float u1, float u2, float& x, float& y) {
    float a = 2.0f * u1 - 1.0f, b = 2.0f * u2 - 1.0f;
    if (a == 0 && b == 0) {
        x = y = 0;
        return;
    }
    float s, c;
    if (std::fabs(a) > std::fabs(b)) {
        sinCosQuarter((kPi / 4) * (b / a), s, c);
        x = a * c;
        y = a * s;
    } else {
        sinCosQuarter((kPi / 4) * (a / b), s, c);
        x = b * s;
        y = b * c;
    }
}
}  // namespace

TEST_CASE("sampleCosineHemispheres equals sampleCosineHemisphere bit for bit", "[sampling]") {
    auto same = [](float p, float q) { return std::memcmp(&p, &q, sizeof p) == 0; };
    std::vector<float> us = {0.0f,    0.5f, 1.0f, 0.25f, 0.75f, std::nextafter(0.5f, 0.0f), std::nextafter(0.5f, 1.0f), std::nextafter(1.0f, 0.0f),
                             0x1p-24f};
    for (int i = 0; i <= 1000; ++i) us.push_back(float(i) / 1000.0f);
    size_t differ = 0, checked = 0;
    for (float u1 : us)
        for (float u2 : us) {
            float x0, y0, x1, y1;
            concentricDiskBranches(u1, u2, x0, y0);
            sampleConcentricDisk(u1, u2, x1, y1);
            differ += same(x0, x1) && same(y0, y1) ? 0 : 1;
            ++checked;
        }
    CHECK(checked > 1000000);
    CHECK(differ == 0);
    std::vector<uint64_t> keys;
    for (uint64_t i = 0; i < (1u << 16); ++i) keys.push_back(mix64(i + 12345));
    const size_t n = keys.size();
    std::vector<float> x(n), y(n), z(n);
    sampleCosineHemispheres(keys.data(), n, 3, 4, x.data(), y.data(), z.data());
    differ = 0;
    for (size_t i = 0; i < n; ++i) {
        const Vec3 w = sampleCosineHemisphere(sampleDimension(keys[i], 3), sampleDimension(keys[i], 4));
        differ += same(w.x, x[i]) && same(w.y, y[i]) && same(w.z, z[i]) ? 0 : 1;
    }
    CHECK(differ == 0);
}

TEST_CASE("uniform triangle warp is uniform in barycentrics", "[sampling]") {
    // Grid over the unit square in (b0, b1); the triangle b0 + b1 <= 1 has area 1/2,
    // so a full cell has probability 2/k^2 and a diagonal cell 1/k^2.
    const int k = 12, N = 400000;
    std::vector<double> obs(k * k, 0.0), expd(k * k, 0.0);
    for (int i = 0; i < k; ++i)
        for (int j = 0; j < k; ++j) expd[i * k + j] = i + j < k - 1 ? 2.0 * N / (k * k) : (i + j == k - 1 ? 1.0 * N / (k * k) : 0.0);
    chi2::Pcg32 g(31);
    double m0 = 0, m1 = 0, m00 = 0, m01 = 0;
    bool valid = true;
    for (int n = 0; n < N; ++n) {
        float b0, b1, u1 = g.uniform(), u2 = g.uniform();
        sampleUniformTriangle(u1, u2, b0, b1);
        valid = valid && b0 >= 0 && b1 >= 0 && b0 + b1 <= 1.0f + 1e-6f;
        obs[std::min(int(b0 * k), k - 1) * k + std::min(int(b1 * k), k - 1)] += 1;
        m0 += b0;
        m1 += b1;
        m00 += double(b0) * b0;
        m01 += double(b0) * b1;
    }
    CHECK(valid);
    auto r = chi2::pearson(obs, expd);
    INFO(chi2::describe(r));
    CHECK(r.pValue > kMinP);
    // Moments of the uniform triangle: E[b] = 1/3, E[b0^2] = 1/6, E[b0 b1] = 1/12;
    // the standard deviations are 0.236, 0.195, 0.097: 5 SE at N = 4e5 below 2e-3.
    CHECK(std::fabs(m0 / N - 1.0 / 3) < 2e-3);
    CHECK(std::fabs(m1 / N - 1.0 / 3) < 2e-3);
    CHECK(std::fabs(m00 / N - 1.0 / 6) < 2e-3);
    CHECK(std::fabs(m01 / N - 1.0 / 12) < 1e-3);
}

TEST_CASE("power heuristic weights form a partition of unity", "[sampling][mis]") {
    chi2::Pcg32 g(41);
    for (int i = 0; i < 10000; ++i) {
        // pdfs spread over 60 orders of magnitude
        float a = std::pow(10.0f, 60.0f * g.uniform() - 30.0f), b = std::pow(10.0f, 60.0f * g.uniform() - 30.0f);
        CHECK(powerHeuristic(a, b) + powerHeuristic(b, a) == Approx(1.0f).epsilon(1e-6));
        CHECK(powerHeuristic(a, b, 1.0f) == Approx(double(a) / (double(a) + b)).epsilon(1e-6).margin(1e-12));
        CHECK(powerHeuristic(a, b, 3.0f) + powerHeuristic(b, a, 3.0f) == Approx(1.0f).epsilon(1e-6));
    }
    CHECK(powerHeuristic(0.0f, 2.0f) == 0.0f);
    CHECK(powerHeuristic(2.0f, 0.0f) == 1.0f);
    CHECK(powerHeuristic(3.0f, 4.0f) == Approx(9.0 / 25.0));

    for (int trial = 0; trial < 2000; ++trial) {
        int n = 2 + int(g.next() % 6);
        float p[8];
        for (int j = 0; j < n; ++j) p[j] = g.uniform() < 0.2f ? 0.0f : std::pow(10.0f, 20.0f * g.uniform() - 10.0f);
        p[0] = std::max(p[0], 1e-3f);  // at least one strategy can sample the path
        for (float beta : {1.0f, 2.0f, 3.5f}) {
            double sum = 0, sumPow = 0;
            for (int j = 0; j < n; ++j) sumPow += std::pow(double(p[j]), double(beta));
            for (int j = 0; j < n; ++j) {
                float w = powerHeuristicN(p, n, j, beta);
                CHECK(w >= 0.0f);
                CHECK(w == Approx(std::pow(double(p[j]), double(beta)) / sumPow).margin(1e-6));
                sum += w;
            }
            CHECK(sum == Approx(1.0).epsilon(1e-5));
        }
        if (n == 2) CHECK(powerHeuristicN(p, 2, 0) == Approx(powerHeuristic(p[0], p[1])));
    }
}

// permuteIndex (rng.h): a bijection of [0, n) for every n and key, and for a fixed i, pi(i)
// is uniform over keys (Pearson, 2 10^5 keys, p = 1e-4, for the first, a middle and the
// last i): so a render stopped inside a round of strata samples each pixel uniformly
// (kernels/camera.h).
TEST_CASE("permuteIndex is a keyed bijection with uniform images", "[sampling][rng]") {
    for (uint32_t n = 1; n <= 600; n += (n < 70 ? 1 : 37))
        for (uint64_t key : {uint64_t(0), uint64_t(1), uint64_t(0x9e3779b97f4a7c15ull), ~uint64_t(0)}) {
            std::vector<int> seen(n, 0);
            bool ok = true;
            for (uint32_t i = 0; i < n; ++i) {
                const uint32_t j = wmlt::permuteIndex(i, n, key);
                ok = ok && j < n && seen[j]++ == 0;
            }
            INFO("n = " << n << ", key " << key);
            CHECK(ok);
        }
    for (uint32_t n : {4u, 9u, 16u, 64u})
        for (uint32_t i : {0u, n / 2, n - 1}) {
            const int keys = 200000;
            std::vector<double> count(n, 0.0);
            for (int k = 0; k < keys; ++k) count[wmlt::permuteIndex(i, n, wmlt::mix64(uint64_t(k) + 12345))] += 1;
            const chi2::Result r = chi2::pearson(count, std::vector<double>(n, double(keys) / n));
            INFO("n = " << n << ", pi(" << i << "): " << chi2::describe(r));
            CHECK(r.pValue > 1e-4);
        }
}

// The camera rays' walks of many indices at once (permuteWalks, in flat loops over the
// values still walking) end where permuteIndex's one-by-one walk does, for widths with no
// walk (n a power of four), short ones and long ones (n just above one).
TEST_CASE("permuteWalks ends every walk where permuteIndex does", "[sampling][rng]") {
    for (uint32_t n : {1u, 2u, 16u, 17u, 25u, 64u, 65u, 121u, 257u}) {
        const size_t m = 3001;
        std::vector<uint32_t> v(m), walkV(m), walkSample(m);
        std::vector<uint64_t> key(m), walkKey(m);
        for (size_t j = 0; j < m; ++j) {
            key[j] = wmlt::mix64(uint64_t(j / 7) + 99);  // runs of one key, as a pixel's samples
            v[j] = uint32_t(j % n);
        }
        wmlt::permuteWalks(n, v.data(), key.data(), m, walkV.data(), walkKey.data(), walkSample.data());
        size_t differ = 0;
        for (size_t j = 0; j < m; ++j) {
            const wmlt::Permutation p(n, key[j]);
            if (p.rotate(v[j]) != wmlt::permuteIndex(uint32_t(j % n), n, key[j]) || !(v[j] < n)) ++differ;
        }
        INFO("n = " << n);
        CHECK(differ == 0);
    }
}
