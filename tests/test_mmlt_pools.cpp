// MMLT's pool weights (poolWeights, mmlt_pool.cpp; SamplePool in mmlt_state.h): they sum to 1,
// they are the plain mean wherever their predictions hold, and a pool of batches whose split
// among the lengths follows the pools' own means (as MMLT's chain allocation does) stays
// unbiased under them, where the plain mean over the samples is biased low (optional
// stopping: the bias the seed room showed, docs/mmlt-levers.md). The last is a Monte Carlo
// model of the render's batches, fixed seed, z-tests at 4.5 standard errors.
#include <catch2/catch.hpp>

#include <cmath>
#include <numeric>
#include <random>
#include <vector>

#include "stages/mmlt/mmlt_stages.h"
#include "stages/mmlt/mmlt_state.h"

using namespace wmlt;

TEST_CASE("MMLT pools: batch weights sum to 1 and are the plain mean where their predictions hold", "[mmlt]") {
    // The bootstrap's halves (50 and 70 samples, shares predicted 0.25 by each other), then
    // three batches of 40 large steps in all of which this length has a quarter, plus 10
    // fresh samples each: every prediction holds, so alpha_b = n_b / sum n.
    std::vector<PoolBatch> b = {{50, 0, 0.25, 1}, {70, 0, 0.25, 1}};
    std::vector<uint64_t> large = {0, 0};
    for (int j = 0; j < 3; ++j) {
        b.push_back({20, 10, 0.25, 1});
        large.push_back(40);
    }
    for (size_t p = 1; p <= b.size(); ++p) {  // every pass's pool: batches 0..p-1
        const std::vector<PoolBatch> pool(b.begin(), b.begin() + long(p));
        const std::vector<uint64_t> pl(large.begin(), large.begin() + long(p));
        const std::vector<double> a = poolWeights(pool, pl, 2);
        double n = 0;
        for (const PoolBatch& x : pool) n += double(x.count);
        INFO("batches " << p);
        CHECK(std::accumulate(a.begin(), a.end(), 0.0) == Approx(1.0).epsilon(1e-12));
        for (size_t i = 0; i < p; ++i) CHECK(a[i] == Approx(double(pool[i].count) / n).epsilon(1e-12));
    }
    // Predictions that fail (a half that predicts far more later samples than come, a batch
    // that predicts fewer, an empty last batch): still a sum of 1, every weight in [0, 1],
    // and nothing for a batch without samples.
    std::vector<PoolBatch> bad = {{50, 0, 0.9, 1}, {70, 0, 0.01, 1}, {5, 5, 0.01, 1}, {300, 10, 0.5, 1}, {0, 0, 0.0, 1}};
    const std::vector<double> a = poolWeights(bad, {0, 0, 1000, 1000, 1000}, 2);
    CHECK(std::accumulate(a.begin(), a.end(), 0.0) == Approx(1.0).epsilon(1e-12));
    for (double x : a) CHECK((x >= 0 && x <= 1));
    CHECK(a[4] == 0.0);
    // Every batch after the bootstrap empty: the bootstrap's halves take all.
    const std::vector<double> first = poolWeights({{50, 0, 0.5, 1}, {70, 0, 0.5, 1}, {0, 0, 0.5, 1}}, {0, 0, 500}, 2);
    CHECK(first[0] == Approx(50.0 / 120));
    CHECK(first[1] == Approx(70.0 / 120));
    CHECK(first[2] == 0.0);
}

namespace {

// A model of a render's pools of two lengths: a sample of length k carries V_k with
// probability p_k, else nothing (b_k = p_k V_k). The bootstrap is two halves of n0 samples
// per length; then each of P passes adds a batch of CL large steps split among the lengths
// in proportion to the pools' estimates (the chain allocation) plus F fresh samples per
// length. Returns the last pool's estimate of each b_k: under poolWeights (exact) or the
// plain mean over all samples (MMLT's pools before 2026-12-06, which also allocated by it).
struct PoolModel {
    double p[2] = {0.01, 0.02}, V[2] = {100.0, 25.0};
    uint64_t n0 = 100, CL = 400, F = 10;
    int P = 4;

    std::vector<double> run(std::mt19937_64& rng, bool exact) const {
        std::vector<PoolBatch> batches[2];
        std::vector<double> sums[2];
        std::vector<uint64_t> large = {0, 0};
        auto draw = [&](int k, uint64_t n) { return double(std::binomial_distribution<uint64_t>(n, p[k])(rng)) * V[k]; };
        auto shares = [](double x0, double x1) {
            const double s = x0 + x1;
            return s > 0 ? std::vector<double>{x0 / s, x1 / s} : std::vector<double>{0.5, 0.5};
        };
        double half[2][2];
        for (int h = 0; h < 2; ++h)
            for (int k = 0; k < 2; ++k) half[h][k] = draw(k, n0);
        for (int h = 0; h < 2; ++h) {
            const std::vector<double> other = shares(half[1 - h][0], half[1 - h][1]);
            for (int k = 0; k < 2; ++k) {
                batches[k].push_back({n0, 0, other[size_t(k)], 1});
                sums[k].push_back(half[h][k]);
            }
        }
        auto estimate = [&](int k) {
            if (!exact) {
                double s = 0, n = 0;
                for (size_t b = 0; b < sums[k].size(); ++b) s += sums[k][b], n += double(batches[k][b].count);
                return s / n;
            }
            const std::vector<double> a = poolWeights(batches[k], large, 2);
            double e = 0;
            for (size_t b = 0; b < a.size(); ++b)
                if (batches[k][b].count) e += a[b] * sums[k][b] / double(batches[k][b].count);
            return e;
        };
        for (int j = 0; j < P; ++j) {
            const std::vector<double> alloc = shares(estimate(0), estimate(1));
            const uint64_t l0 = uint64_t(std::llround(double(CL) * alloc[0])), l[2] = {l0, CL - l0};
            for (int k = 0; k < 2; ++k) {
                batches[k].push_back({l[k] + F, F, double(l[k]) / double(CL), 1});
                sums[k].push_back(draw(k, l[k] + F));
            }
            large.push_back(CL);
        }
        return {estimate(0), estimate(1)};
    }
};

}  // namespace

TEST_CASE("MMLT pools: batches split by the pools' own means stay unbiased under their weights, the plain mean does not", "[mmlt]") {
    const PoolModel m;
    const int T = 20000;
    for (bool exact : {true, false}) {
        std::mt19937_64 rng(exact ? 4401 : 4402);
        double s[2] = {0, 0}, s2[2] = {0, 0};
        for (int t = 0; t < T; ++t) {
            const std::vector<double> e = m.run(rng, exact);
            for (int k = 0; k < 2; ++k) {
                const double r = e[size_t(k)] / (m.p[k] * m.V[k]);
                s[k] += r;
                s2[k] += r * r;
            }
        }
        for (int k = 0; k < 2; ++k) {
            const double mean = s[k] / T, se = std::sqrt((s2[k] / T - mean * mean) / (T - 1)), z = (mean - 1) / se;
            INFO((exact ? "weighted" : "plain") << " pools, length " << k << ": mean / b_k " << mean << " +- " << se << " (z " << z << ")");
            if (exact) CHECK(std::abs(z) < 4.5);
            else CHECK(z < -10);  // the model has the power to see the bias the weights remove
        }
    }
}
