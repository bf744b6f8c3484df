// The Metropolis kernel of kernels/mutation.h: coordinates stay in [0, 1), Phi^-1 is accurate,
// the lazy small step equals the eager one in distribution, and Metropolis chains built from
// proposeCoordinate and acceptance sample known 1-D and 2-D densities (chi-square tests with
// fixed seeds and a fixed false-alarm probability per check).
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <complex>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "chi2.h"
#include "kernels/gaussian.h"
#include "kernels/mutation.h"
#include "render_stats.h"
#include "stages/mmlt/mmlt_stages.h"
#include "stages/mmlt/mmlt_state.h"

using namespace wmlt;

namespace {
constexpr double kMinP = 1e-4;  // false-alarm probability of each statistical check

struct Rng {
    std::mt19937_64 g;
    explicit Rng(uint64_t seed) : g(seed) {}
    float uniform() { return float(g() >> 40) * 0x1p-24f; }  // [0, 1), 24 bits
    double uniformD() { return double(g() >> 11) * 0x1p-53; }
    bool bernoulli(double p) { return uniformD() < p; }
};

// Two histograms of equal totals: sum (a - b)^2 / (a + b) ~ chi^2(bins - 1) when both come
// from the same distribution (Press et al., Numerical Recipes, 14.3).
chi2::Result twoSampleChi2(const std::vector<double>& a, const std::vector<double>& b) {
    chi2::Result r;
    for (size_t i = 0; i < a.size(); ++i)
        if (a[i] + b[i] > 0) {
            r.stat += (a[i] - b[i]) * (a[i] - b[i]) / (a[i] + b[i]);
            ++r.dof;
        }
    r.dof -= 1;
    r.pValue = chi2::gammaQ(0.5 * r.dof, 0.5 * r.stat);
    return r;
}

// ---- targets with known bin probabilities -------------------------------------------------

// 1-D: a smooth part and a peak (edges at multiples of 1/100, so that the 100 bins resolve it)
// whose sharp edges make small-step errors visible within a few steps of sigma = 0.01.
double target1(double x) { return 1 + 0.8 * std::sin(2 * M_PI * x) + (x >= 0.3 && x < 0.35 ? 8.0 : 0.0); }
constexpr double kTarget1Max = 9.8, kTarget1Integral = 1.4;
double target1Mass(double a, double b) {  // integral over [a, b] / kTarget1Integral
    double peak = std::max(0.0, std::min(b, 0.35) - std::max(a, 0.3));
    return ((b - a) + 0.8 / (2 * M_PI) * (std::cos(2 * M_PI * a) - std::cos(2 * M_PI * b)) + 8 * peak) / kTarget1Integral;
}

// 2-D, not separable: 1 + 0.9 cos(2 pi (x + y)) plus a peak on [0.5, 0.6)^2 (edges on the
// 20 x 20 bin grid).
double target2(double x, double y) {
    bool peak = x >= 0.5 && x < 0.6 && y >= 0.5 && y < 0.6;
    return 1 + 0.9 * std::cos(2 * M_PI * (x + y)) + (peak ? 20.0 : 0.0);
}
constexpr double kTarget2Max = 21.9, kTarget2Integral = 1.2;
double target2Mass(double x0, double x1, double y0, double y1) {
    // Integral of cos(2 pi (x + y)) = Re of the product of the integrals of exp(2 pi i x), exp(2 pi i y).
    auto e = [](double t) { return std::exp(std::complex<double>(0, 2 * M_PI * t)); };
    std::complex<double> c = (e(x1) - e(x0)) * (e(y1) - e(y0)) / (-4 * M_PI * M_PI);
    double ox = std::max(0.0, std::min(x1, 0.6) - std::max(x0, 0.5));
    double oy = std::max(0.0, std::min(y1, 0.6) - std::max(y0, 0.5));
    return ((x1 - x0) * (y1 - y0) + 0.9 * c.real() + 20 * ox * oy) / kTarget2Integral;
}

// ---- Metropolis chains in primary sample space ----------------------------------------------

// One chain over D coordinates, with the state and the protocol of the renderer: the counter
// counts accepted proposals, every coordinate is read each iteration, a proposal is committed
// only when accepted. Starts from an exact sample of f (rejection sampling), so that it is
// stationary from the start: the state after any number of steps is again an exact sample.
template <int D, class F>
struct Chain {
    using Point = std::array<float, D>;
    F f;
    Point x{};
    std::array<uint32_t, D> lastModified{};
    uint32_t accepted = 0, lastLargeStep = 0;
    double fx = 0;

    Chain(F f, double fMax, Rng& rng) : f(f) {
        do {
            for (float& v : x) v = rng.uniform();
            fx = eval(x);
        } while (rng.uniformD() * fMax >= fx);
    }
    double eval(const Point& p) const {
        if constexpr (D == 1) return f(p[0]);
        else return f(p[0], p[1]);
    }
    // One iteration; splat(a, proposal, current) sees the acceptance probability.
    template <class Splat>
    void step(Rng& rng, double pLarge, Splat&& splat) {
        bool large = rng.bernoulli(pLarge);
        uint32_t n = accepted + 1;
        Point y;
        for (int j = 0; j < D; ++j)
            y[j] = proposeCoordinate(x[j], lastModified[j], lastLargeStep, n, large, kSmallStepSigma, rng.uniform(), standardNormal(rng.g(), 0));
        double fy = eval(y);
        float a = acceptance(float(fy), float(fx));
        splat(a, y, x);
        if (rng.uniformD() < a) {
            x = y;
            fx = fy;
            for (uint32_t& m : lastModified) m = n;
            accepted = n;
            if (large) lastLargeStep = n;
        }
    }
};

int bin1(float x, int bins) { return std::min(int(x * bins), bins - 1); }

}  // namespace

TEST_CASE("wrapUnit and proposeCoordinate stay in the unit interval", "[mutation]") {
    auto inUnit = [](float v) { return v >= 0.0f && v < 1.0f; };
    const float one = 0x1.fffffep-1f;  // 0.99999994f, the largest float below 1
    const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
    for (float x : {-1e-30f, -0.0f, 0.0f, 1.0f, one, one + kSmallStepSigma, -one, -1.0f, 1e30f, -1e30f, -std::numeric_limits<float>::denorm_min(),
                    8388607.5f, -8388607.5f, inf, -inf, nan}) {
        CAPTURE(x);
        CHECK(inUnit(wrapUnit(x)));
    }
    CHECK(wrapUnit(-1e-30f) == 0.0f);
    CHECK(wrapUnit(1.0f) == 0.0f);
    CHECK(wrapUnit(-0.25f) == 0.75f);
    CHECK(wrapUnit(2.5f) == 0.5f);
    CHECK(wrapUnit(0.375f) == 0.375f);

    Rng rng(7);
    int bad = 0;
    for (int i = 0; i < 200000; ++i) {  // random finite floats of every magnitude
        uint32_t bits = uint32_t(rng.g());
        float x;
        std::memcpy(&x, &bits, sizeof x);
        if (std::isfinite(x) && !inUnit(wrapUnit(x))) ++bad;
    }
    CHECK(bad == 0);

    const uint32_t maxN = std::numeric_limits<uint32_t>::max();
    for (float value : {0.0f, 0.5f, one})
        for (float sigma : {kSmallStepSigma, 1.0f, 1e6f})
            for (float uFresh : {0.0f, 0.5f, one})
                for (float z : {0.0f, 1e-30f, 5.4f, -5.4f, 40.0f})
                    for (uint32_t lastModified : {0u, 1u, maxN - 1})
                        for (uint32_t lastLarge : {0u, 1u, maxN - 1})
                            for (uint32_t n : {2u, maxN})
                                for (bool large : {false, true}) {
                                    if (lastModified >= n || lastLarge >= n) continue;
                                    float v = proposeCoordinate(value, lastModified, lastLarge, n, large, sigma, uFresh, z);
                                    CAPTURE(value, sigma, uFresh, z, lastModified, lastLarge, n, large, v);
                                    REQUIRE(inUnit(v));
                                }
}

TEST_CASE("the ziggurat's layers have equal areas and cover the normal density", "[mutation]") {
    const ZigguratTables& z = kZiggurat;
    const int n = ZigguratTables::kLayers;
    auto f = [](double x) { return std::exp(-0.5 * x * x); };
    // Layer i >= 1: the rectangle x_i (f(x_{i+1}) - f(x_i)); the base: r f(r) plus the tail.
    const double tail = std::sqrt(M_PI / 2) * std::erfc(kZigguratR / std::sqrt(2.0));
    CHECK(z.x[0] * f(kZigguratR) == Approx(kZigguratV).epsilon(1e-12));
    CHECK(kZigguratR * f(kZigguratR) + tail == Approx(kZigguratV).epsilon(1e-9));
    double worst = 0;
    for (int i = 1; i < n; ++i) {
        CHECK(z.x[i + 1] < z.x[i]);
        worst = std::max(worst, std::fabs(z.x[i] * (f(z.x[i + 1]) - f(z.x[i])) / kZigguratV - 1));
    }
    CAPTURE(worst);
    CHECK(worst < 1e-8);  // the top layer (up to f(0) = 1) closes the recursion
}

TEST_CASE("standardNormal has the normal distribution, tails included", "[mutation]") {
    // 4e6 draws from consecutive keys, binned at the quantiles of 200 equal-probability bins
    // plus 8 bins finer in each tail (to 1e-7): chi-square at p = kMinP; mean and variance
    // within 5 standard errors; the fraction of draws that took the slow path as the tables
    // say (1 - mean of x_{i+1} / x_i: about 2.8%).
    const int draws = 4000000;
    std::vector<double> edges;
    for (double p : {1e-7, 1e-6, 1e-5, 1e-4, 1e-3}) edges.push_back(rstats::normalQuantile(p));
    for (int i = 1; i < 200; ++i) edges.push_back(rstats::normalQuantile(i / 200.0));
    for (double p : {1e-3, 1e-4, 1e-5, 1e-6, 1e-7}) edges.push_back(-rstats::normalQuantile(p));
    std::sort(edges.begin(), edges.end());
    std::vector<double> count(edges.size() + 1, 0.0);
    double sum = 0, sum2 = 0;
    int slow = 0;
    for (int i = 0; i < draws; ++i) {
        const uint64_t key = mix64(uint64_t(i) + 12345);
        const float x = standardNormal(key, 7);
        const uint64_t h = normalBits(key, 7, 0);
        slow += !(double(h >> 11) * 0x1p-53 < kZiggurat.inner[h & 127]);
        count[std::upper_bound(edges.begin(), edges.end(), double(x)) - edges.begin()] += 1;
        sum += x;
        sum2 += double(x) * x;
    }
    chi2::Result r;
    for (size_t b = 0; b < count.size(); ++b) {
        const double lo = b == 0 ? 0.0 : rstats::normalCdf(edges[b - 1]);
        const double hi = b == edges.size() ? 1.0 : rstats::normalCdf(edges[b]);
        const double expected = (hi - lo) * draws;
        r.stat += (count[b] - expected) * (count[b] - expected) / expected;
        ++r.dof;
    }
    r.dof -= 1;
    r.pValue = chi2::gammaQ(0.5 * r.dof, 0.5 * r.stat);
    const double mean = sum / draws, var = sum2 / draws - mean * mean;
    CAPTURE(r.stat, r.dof, r.pValue, mean, var, slow);
    CHECK(r.pValue > kMinP);
    CHECK(std::fabs(mean) < 5 / std::sqrt(double(draws)));
    CHECK(std::fabs(var - 1) < 5 * std::sqrt(2.0 / draws));
    double inner = 0;
    for (double q : kZiggurat.inner) inner += q / ZigguratTables::kLayers;
    const double pSlow = 1 - inner;
    CAPTURE(pSlow);
    CHECK(std::fabs(slow - pSlow * draws) < 5 * std::sqrt(draws * pSlow * (1 - pSlow)));
    // A pure function of (key, dim): the same number again, another for another dim.
    CHECK(standardNormal(42, 3) == standardNormal(42, 3));
    CHECK(standardNormal(42, 3) != standardNormal(42, 5));
}

TEST_CASE("proposeCoordinate follows the lazy update rule", "[mutation]") {
    const float s = kSmallStepSigma, z = 0.8416212f;
    // Large step: the fresh value.
    CHECK(proposeCoordinate(0.3f, 2, 1, 5, true, s, 0.9f, z) == 0.9f);
    // Up to date (written at or after the last large step): value + sigma sqrt(n - lastModified) z.
    CHECK(proposeCoordinate(0.3f, 4, 1, 5, false, s, 0.9f, 0.0f) == 0.3f);
    CHECK(proposeCoordinate(0.3f, 3, 3, 4, false, s, 0.9f, 0.0f) == 0.3f);
    CHECK(proposeCoordinate(0.3f, 1, 0, 5, false, s, 0.9f, z) == Approx(0.3 + s * 2 * z).margin(1e-6));
    // Stale (a large step accepted since): uFresh at lastLargeStep, then n - lastLargeStep steps.
    CHECK(proposeCoordinate(0.3f, 1, 3, 12, false, s, 0.9f, z) == Approx(0.9 + s * 3 * z).margin(1e-6));
    // Wrapping.
    CHECK(proposeCoordinate(0.995f, 1, 0, 2, false, s, 0.9f, z) == Approx(0.995 + s * z - 1).margin(1e-6));
}

TEST_CASE("acceptance is min(1, ratio) and never accepts an invalid proposal", "[mutation]") {
    const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
    CHECK(acceptance(1.0f, 4.0f) == 0.25f);
    CHECK(acceptance(4.0f, 1.0f) == 1.0f);
    CHECK(acceptance(3.0f, 3.0f) == 1.0f);
    for (float bad : {0.0f, -0.0f, -1.0f, inf, -inf, nan}) {
        CAPTURE(bad);
        CHECK(acceptance(bad, 1.0f) == 0.0f);
        CHECK(acceptance(bad, 0.0f) == 0.0f);
    }
    CHECK(acceptance(2.0f, 0.0f) == 1.0f);
    CHECK(acceptance(2.0f, -1.0f) == 1.0f);
}

TEST_CASE("lazy small steps equal eager ones in distribution", "[mutation]") {
    // One coordinate through T iterations of a chain whose proposals are large with
    // probability pLarge and accepted with probability pAccept; the coordinate is read with
    // probability pRead, and always at iteration T, which is a small step. The value read at
    // T, lazily (proposeCoordinate when read, committed on accept) and eagerly (every accepted
    // small step adds one N(0, sigma^2) step, every accepted large step regenerates it), must
    // have the same distribution: histograms over many replicas, two-sample chi-square. The
    // start value 0.98 makes the steps wrap; 1 - (1 - pLarge pAccept)^(T-1) ~ 3/4 of the
    // replicas have seen an accepted large step and are uniform, the rest show the spread.
    const int T = 24, replicas = 200000, bins = 100;
    const double pLarge = 0.1, pRead = 0.3, pAccept = 0.6;
    const float x0 = 0.98f, sigma = kSmallStepSigma;
    std::vector<double> lazy(bins, 0.0), eager(bins, 0.0);

    Rng rl(11);
    for (int r = 0; r < replicas; ++r) {
        float value = x0;
        uint32_t lastModified = 0, lastLargeStep = 0, accepted = 0;
        for (int it = 1; it <= T; ++it) {
            bool last = it == T, large = !last && rl.bernoulli(pLarge);
            bool read = last || rl.bernoulli(pRead), accept = rl.bernoulli(pAccept);
            uint32_t n = accepted + 1;  // proposal n: counts accepted proposals only
            if (read) {
                float v = proposeCoordinate(value, lastModified, lastLargeStep, n, large, sigma, rl.uniform(), standardNormal(rl.g(), 0));
                if (last) {
                    lazy[bin1(v, bins)] += 1;
                    break;
                }
                if (accept) {
                    value = v;
                    lastModified = n;
                }
            }
            if (accept) {
                accepted = n;
                if (large) lastLargeStep = n;
            }
        }
    }
    Rng re(12);
    std::normal_distribution<double> normal;
    for (int r = 0; r < replicas; ++r) {
        double value = x0;
        for (int it = 1; it <= T; ++it) {
            bool last = it == T, large = !last && re.bernoulli(pLarge), accept = re.bernoulli(pAccept);
            double v = large ? re.uniformD() : value + sigma * normal(re.g);
            v -= std::floor(v);
            if (last) {
                eager[bin1(float(v), bins)] += 1;
                break;
            }
            if (accept) value = v;
        }
    }
    auto res = twoSampleChi2(lazy, eager);
    INFO(chi2::describe(res));
    CHECK(res.dof == bins - 1);
    CHECK(res.pValue > kMinP);
}

TEST_CASE("Metropolis chains sample a 1-D density", "[mutation]") {
    // N chains started from exact samples of f run M iterations each: if the kernel leaves f
    // invariant, the final states are N independent samples of f. Pearson's test on 100 bins.
    const int chains = 20000, steps = 64, bins = 100;
    std::vector<double> expected(bins);
    for (int b = 0; b < bins; ++b) expected[b] = chains * target1Mass(double(b) / bins, double(b + 1) / bins);
    for (double pLarge : {0.3, 0.0}) {
        Rng rng(pLarge > 0 ? 21 : 22);
        std::vector<double> observed(bins, 0.0);
        for (int c = 0; c < chains; ++c) {
            Chain<1, decltype(&target1)> chain(&target1, kTarget1Max, rng);
            for (int m = 0; m < steps; ++m) chain.step(rng, pLarge, [](float, auto&, auto&) {});
            observed[bin1(chain.x[0], bins)] += 1;
        }
        auto res = chi2::pearson(observed, expected);
        CAPTURE(pLarge);
        INFO(chi2::describe(res));
        CHECK(res.pValue > kMinP);
    }
}

TEST_CASE("Metropolis chains sample a non-separable 2-D density", "[mutation]") {
    const int chains = 40000, steps = 64, bins = 20;  // 20 x 20 bins
    std::vector<double> expected(bins * bins);
    for (int i = 0; i < bins; ++i)
        for (int j = 0; j < bins; ++j)
            expected[i * bins + j] = chains * target2Mass(double(i) / bins, double(i + 1) / bins, double(j) / bins, double(j + 1) / bins);
    for (double pLarge : {0.3, 0.0}) {
        Rng rng(pLarge > 0 ? 31 : 32);
        std::vector<double> observed(bins * bins, 0.0);
        for (int c = 0; c < chains; ++c) {
            Chain<2, decltype(&target2)> chain(&target2, kTarget2Max, rng);
            for (int m = 0; m < steps; ++m) chain.step(rng, pLarge, [](float, auto&, auto&) {});
            observed[bin1(chain.x[0], bins) * bins + bin1(chain.x[1], bins)] += 1;
        }
        auto res = chi2::pearson(observed, expected);
        CAPTURE(pLarge);
        INFO(chi2::describe(res));
        CHECK(res.pValue > kMinP);
    }
}

TEST_CASE("expected-value splats reproduce the 1-D density", "[mutation]") {
    // Each iteration adds a to the proposal's bin and 1 - a to the current state's bin
    // (Veach 1997, 11.4.2); a chain's histogram divided by its iteration count estimates the
    // bin probabilities. The chains are independent: per bin, z = (mean - p) / se with se
    // from the chains' scatter is N(0, 1) (normal limit, N = 20000), and max |z| over the bins
    // stays below the Bonferroni bound Phi^-1(1 - kMinP / (2 bins)) with probability >= 1 - kMinP.
    const int chains = 20000, steps = 64, bins = 100;
    const double bound = -rstats::normalQuantile(kMinP / (2 * bins));
    for (double pLarge : {0.3, 0.0}) {
        Rng rng(pLarge > 0 ? 41 : 42);
        std::vector<double> sum(bins, 0.0), sumSq(bins, 0.0), h(bins);
        for (int c = 0; c < chains; ++c) {
            std::fill(h.begin(), h.end(), 0.0);
            Chain<1, decltype(&target1)> chain(&target1, kTarget1Max, rng);
            for (int m = 0; m < steps; ++m)
                chain.step(rng, pLarge, [&](float a, auto& proposal, auto& current) {
                    h[bin1(proposal[0], bins)] += a;
                    h[bin1(current[0], bins)] += 1 - a;
                });
            for (int b = 0; b < bins; ++b) {
                sum[b] += h[b] / steps;
                sumSq[b] += (h[b] / steps) * (h[b] / steps);
            }
        }
        double maxZ = 0;
        int worst = 0;
        for (int b = 0; b < bins; ++b) {
            double mean = sum[b] / chains, var = (sumSq[b] - chains * mean * mean) / (chains - 1);
            double z = (mean - target1Mass(double(b) / bins, double(b + 1) / bins)) / std::sqrt(var / chains);
            if (!(std::fabs(z) <= maxZ)) {
                maxZ = std::fabs(z);
                worst = b;
            }
        }
        CAPTURE(pLarge, maxZ, bound, worst);
        CHECK(maxZ <= bound);
    }
}

// MMLT's rows hold only the numbers a proposal's strategy reads (mmlt_stages.cpp,
// forEachUsedOf): a number the walks read but the fill skips keeps what the batch's last
// task left there, and the image then depends on the thread schedule. At MaxPathLength 64
// the camera subpath of strategy s = 0 reads 4 * 65 - 4 = 256 numbers, one more than a
// uint8_t counts (it wrapped to 0: no camera number was filled; the stability test saw it
// as an image that changed from run to run). Every strategy of every length is checked.
TEST_CASE("MMLT pool rows fill every number the strategy's walks read, up to length 64", "[mutation][mmlt]") {
    using namespace wmlt;
    constexpr uint32_t n = 256;
    MmltBatch mb;
    mb.reserve(n, kMaxPathLength, BatchNeeds{});
    mb.lensRead = true;  // a thin lens reads the lens pair; every kind's lobe and direction
    mb.vertexLo = 0;
    mb.vertexHi = 3;
    const float unset = std::numeric_limits<float>::quiet_NaN();
    for (int k = 1; k <= kMaxPathLength; ++k) {
        std::vector<int> seen(size_t(k) + 1, 0);
        size_t missing = 0, checked = 0;
        for (uint32_t index0 = 0; index0 < 64 * n && std::count(seen.begin(), seen.end(), 0) > 0; index0 += n) {
            std::fill(mb.u.begin(), mb.u.end(), unset);
            fillPoolRows(mb, k, 0, index0, n, 7);
            const StoredSamples u = mb.samples();
            for (uint32_t i = 0; i < n; ++i) {
                const int s = mb.bpt.strategyS[i], t = k + 1 - s;
                seen[size_t(s)] = 1;
                auto check = [&](BptStream c, uint32_t j) {
                    ++checked;
                    if (std::isnan(u(i, c, j))) ++missing;
                };
                if (t >= 2) {  // raster and lens point, then the BSDF at z_1 .. z_{t-2}
                    for (uint32_t j = 0; j < 4; ++j) check(kBptCamera, j);
                    for (int d = 1; d <= t - 2; ++d)
                        for (uint32_t m = 0; m < 3; ++m) check(kBptCamera, bptCamVertexJ(d, m));
                }
                if (s >= 2 || (s == 1 && t == 1)) {  // y_0 and its direction, then the BSDF at y_1 .. y_{s-2}
                    for (uint32_t j = 0; j < 5; ++j) check(kBptLight, j);
                    for (int d = 1; d <= s - 2; ++d)
                        for (uint32_t m = 0; m < 3; ++m) check(kBptLight, bptLightVertexJ(d, m));
                }
                if (s == 1 && t >= 2)
                    for (uint32_t m = 0; m < 3; ++m) check(kBptConnect, m);
                if (t == 1)
                    for (uint32_t m = 0; m < 2; ++m) check(kBptConnect, m);
            }
        }
        INFO("length " << k << ": " << missing << " of " << checked << " numbers read were not filled");
        CHECK(std::count(seen.begin(), seen.end(), 0) == 0);
        CHECK(missing == 0);
    }
}

// thinPool's threshold (thinningThreshold: passes to a fixed point) against its definition
// over the sorted values (the m largest kept whole, the rest at level tau = (the sum of the
// others) / (keep - m), the least m with v_(m) < tau), and the level's defining sum
// sum_i min(1, v_i / tau) = keep; for even, spread and heavy-tailed pools and a pool with
// a few values far above the rest. Then thinPool itself: about keep entries, every kept
// entry's w c at least tau, and the comb keeps the pool's sum of w c within tau.
TEST_CASE("MMLT pool thinning: the threshold matches its definition, the thinned pool keeps the sum", "[mmlt][pool]") {
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    for (int kind = 0; kind < 4; ++kind)
        for (size_t n : {size_t(3), size_t(100), size_t(20000)})
            for (size_t keep : {size_t(1), n / 2 + 1, n - 1}) {
                if (keep >= n || keep == 0) continue;
                wmlt::SamplePool pool;
                for (size_t i = 0; i < n; ++i) {
                    const double u = u01(rng);
                    double c = kind == 0 ? 1.0 : kind == 1 ? 0.01 + u : kind == 2 ? std::pow(1.0 - u, -1.5) : (i % 997 == 0 ? 1e6 : 1.0 + u);
                    pool.lit.push_back({rng(), float(c), float(0.5 + u01(rng)), wmlt::Vec3(1.0f), float(i), 0.0f, 0});
                    pool.sumWC += double(pool.lit.back().w) * double(pool.lit.back().c);
                }
                std::vector<double> v;
                for (const wmlt::PoolEntry& x : pool.lit) v.push_back(double(x.w) * double(x.c));
                std::sort(v.begin(), v.end(), std::greater<double>());
                std::vector<double> suffix(v.size() + 1, 0.0);
                for (size_t i = v.size(); i-- > 0;) suffix[i] = suffix[i + 1] + v[i];
                double ref = 0;
                for (size_t m = 0; m < keep; ++m) {
                    ref = suffix[m] / double(keep - m);
                    if (v[m] < ref) break;
                }
                const double tau = wmlt::thinningThreshold(pool.lit, keep);
                double places = 0;
                for (double x : v) places += std::min(1.0, x / tau);
                INFO("kind " << kind << ", n " << n << ", keep " << keep << ": tau " << tau << ", sorted " << ref);
                CHECK(std::fabs(tau - ref) <= 1e-12 * ref);
                CHECK(std::fabs(places - double(keep)) <= 1e-9 * double(keep));
                const double before = pool.sumWC;
                wmlt::thinPool(pool, keep, 99, uint32_t(kind));
                CHECK(pool.lit.size() + 1 >= keep);
                CHECK(pool.lit.size() <= keep + 1);
                double after = 0;
                size_t below = 0;
                for (const wmlt::PoolEntry& x : pool.lit) {
                    after += double(x.w) * double(x.c);
                    if (double(x.w) * double(x.c) < tau * (1 - 1e-6)) ++below;
                }
                CHECK(below == 0);
                CHECK(std::fabs(after - pool.sumWC) <= 1e-9 * after);
                CHECK(std::fabs(after - before) <= tau * (1 + 1e-9));
            }
}
