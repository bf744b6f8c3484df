// MMLT's pools (mmlt_render.h): the bootstrap, tracing fresh samples of every length, and,
// split across ranks, exchanging every task's pool samples so that every rank merges the
// same pools; the weights of a pool's batches (poolWeights) and its thinning (thinPool).
#include "stages/mmlt/mmlt_render.h"

namespace wmlt::mmlt_detail {

// Fresh samples [from, to[k]) of every length k (pass pass_) into the pools `into`, in
// parallel tasks merged in task order (with `odd`: the tasks of odd chunks of
// kBatchChains samples there). The bootstrap under a time budget stops early once it has
// spent 5% of the budget; false when it was stopped (by the budget or a cancel, as all
// ranks agree).
bool MmltRender::tracePool(uint32_t from, const std::vector<uint32_t>& to, bool bootstrap, std::vector<SamplePool>& into,
                           std::vector<SamplePool>* odd) {
    const uint32_t chunk = kBatchChains;
    uint32_t done = from;
    const uint32_t most = *std::max_element(to.begin(), to.end());
    // Under a time budget the bootstrap runs in slabs that grow while they are short (64
    // samples per length, then about 1% of the budget each), so that it can stop on time.
    // Otherwise a slab is about 4096 samples per thread (of every rank) in all lengths, so
    // that Ctrl-C is heard within a fraction of a second (mpirun kills the ranks about a
    // second after it); those slabs are whole tasks, so the pools do not depend on them
    // (each length's tasks are added in order, and their sums in the same tasks; from is
    // a multiple of the chunk or the end).
    const double workers = double(tbb::this_task_arena::max_concurrency()) * (ranks_ ? ranks_->size() : 1);
    uint32_t slabSize = bootstrap && timed() ? 64 : chunk * uint32_t(std::ceil(4096.0 * workers / double(hi_ - lo_ + 1) / double(chunk)));
    while (done < most) {
        const double start = elapsed();
        const uint32_t slab = std::min(most - done, slabSize);
        std::vector<PoolTask> tasks;
        uint64_t samples = 0;
        for (int k = lo_; k <= hi_; ++k) {
            const uint32_t end = std::min(done + slab, to[size_t(k)]);
            for (uint32_t i = done; i < end; i += chunk) tasks.push_back({k, i, std::min(chunk, end - i)});
            samples += end > done ? end - done : 0;
        }
        std::vector<SamplePool> out(tasks.size()), outMap(tasks.size());  // the pools', the target map's
        std::vector<uint64_t> nonfinite(tasks.size(), 0);
        std::vector<double> taskSeconds(tasks.size(), 0.0);
        const auto [t0, t1] = shareOf(ranks_, tasks.size());  // this rank's tasks
        tbb::parallel_for(t0, t1, [&](size_t ti) {
            const Clock::time_point taskStart = Clock::now();
            const PoolTask& t = tasks[ti];
            MmltBatch& mb = batches_.local();
            mb.counters.nonfinite = 0;
            mb.target = map_;
            mb.splitForMap = !brightness_.empty();
            stages_.fillPoolRows(mb, t.k, pass_, t.i0, t.n, opt_.seed);
            stages_.evaluateProposals(scene_, mb, opt_.misBeta, rays_.local());
            stages_.addPoolSamples(mb, t.n, out[ti]);
            std::swap(outMap[ti], mb.mapPools[size_t(t.k)]);
            mb.mapPools[size_t(t.k)].clear();
            nonfinite[ti] = mb.counters.nonfinite;
            taskSeconds[ti] = std::chrono::duration<double>(Clock::now() - taskStart).count();
        });
        exchangePools(out, t0, t1 - t0);
        if (!brightness_.empty()) exchangePools(outMap, t0, t1 - t0);
        for (size_t ti = 0; ti < tasks.size(); ++ti) {
            const bool isOdd = odd && (tasks[ti].i0 / chunk) % 2 == 1;
            (isOdd ? *odd : into)[size_t(tasks[ti].k)].add(out[ti]);
            collectBrightness(outMap[ti], tasks[ti].k);
            counters_.nonfinite += nonfinite[ti];
        }
        done += slab;
        sampleSeconds_ = (elapsed() - start) / double(samples);
        if (bootstrap) sampleSeconds_ *= chainCostRatio(tasks, taskSeconds, t0, t1);
        // The next slab, rank 0's figure (0: the timed bootstrap has spent its 5%).
        uint64_t next = slabSize;
        if (bootstrap && timed()) {
            int active = 0;  // lengths that want more samples
            for (int k = lo_; k <= hi_; ++k) active += to[size_t(k)] > done ? 1 : 0;
            const double perSlab = 0.01 * opt_.timeBudget / (sampleSeconds_ * std::max(active, 1));
            next = elapsed() >= 0.05 * opt_.timeBudget ? 0 : uint64_t(std::clamp(perSlab, 64.0, double(1 << 16)));
        }
        const Agreement a = agreeAtBoundary(next);
        if (a.value == 0 || a.cancel) break;
        slabSize = uint32_t(a.value);
    }
    const bool complete = done >= most;
    if (bootstrap)
        for (int k = lo_; k <= hi_; ++k) stats_.bootstrapSamples[size_t(k)] = std::min(done, to[size_t(k)]) - from;
    return complete;
}

// The bootstrap (mmlt.md, step 1; docs/mmlt-chains.md, "Where it departs"): a probe of 256
// samples of every length, then each length gets its share of the whole: half of it in
// equal parts, half in proportion to its b_k as the probe estimates it (its share of the
// chains and of the mutations: where the seeds are needed), at least 512. The whole is 5%
// of the mutations asked for or two per chain, whichever is more, so the bootstrap costs
// about 5% of them. (All of it by the probe's b_k starved the lengths the probe saw no light
// in: in the seed room, where 0.6% of the samples carry light, the probe's 256 often see
// none; all of it in equal parts spent most of it on the long lengths, whose samples cost
// the most and which get few chains.) The probe joins no pool: the bootstrap's sizes depend
// on its values; what it saw also plans the passes (probeLit_, planPasses). Under a time
// budget the whole is 2^20 samples per length, so that tracePool's stop at 5% of the budget
// ends the bootstrap (if that is in the probe, the probe is the first pool) with every
// length at the same count. (A whole sized to fit that 5% at the probe's cost per sample
// of each length, which gives the lit lengths more, was measured against it on the
// estimator suite's scenes, 3 seeds at 2 and 6 s, 2026-12-07: relMSE 0.98 to 1.46 of it,
// no gain on any scene, so not kept.) --bootstrap N: N samples of every length, in one
// step, the first pool. Either way the first pool is two batches, its even and odd chunks
// of 256 samples (closeBootstrap).
void MmltRender::bootstrap() {
    const int nLengths = hi_ - lo_ + 1;
    const double whole = timed() ? double(1 << 20) * nLengths : std::max(0.05 * targetMutations_, 2.0 * chains_);
    const bool fixed = opt_.bootstrap > 0;
    const uint32_t probe = fixed ? uint32_t(opt_.bootstrap) : kBatchChains;
    std::vector<uint32_t> to(size_t(kMax_) + 1, probe);
    std::vector<SamplePool> even(size_t(kMax_) + 1), odd(size_t(kMax_) + 1);
    if (!tracePool(0, to, true, even, &odd) || fixed) return closeBootstrap(even, odd);
    for (int k = lo_; k <= hi_; ++k) even[size_t(k)].add(odd[size_t(k)]);
    chainShare_ = shares(even);
    probeLit_.assign(size_t(kMax_) + 1, 0.0);
    for (int k = lo_; k <= hi_; ++k) {
        const double share = chainShare_[size_t(k)];
        to[size_t(k)] = probe + uint32_t(std::clamp(std::ceil(whole * (0.5 / nLengths + 0.5 * share)), 2.0 * probe, double(1 << 20)));
        probeLit_[size_t(k)] = double(even[size_t(k)].lit.size()) / double(probe);  // (times the samples traced, below)
        even[size_t(k)].clear();
        odd[size_t(k)].clear();
    }
    tracePool(probe, to, true, even, &odd);
    for (int k = lo_; k <= hi_; ++k) probeLit_[size_t(k)] *= double(stats_.bootstrapSamples[size_t(k)]);
    closeBootstrap(even, odd);
}

// A chain's iteration costs about a pool sample of its length, and the chains are spread over
// the lengths unlike the bootstrap (half of it equally): the slab's cost per sample of each
// length weighted by its predicted share of the chains (chainShare_, the probe's b_k) over the
// slab's cost per sample, from the CPU seconds of this rank's tasks (a length none of them
// traced costs the average). 1 before the probe has spoken. The Cornell box at MaxPathLength
// 64 and --time 6: the bootstrap's wall time per sample overstated a mutation's 3-fold, and
// planned 1024 chains where the old split planned 1792.
double MmltRender::chainCostRatio(const std::vector<PoolTask>& tasks, const std::vector<double>& taskSeconds, size_t t0, size_t t1) const {
    if (chainShare_.empty()) return 1.0;
    std::vector<double> seconds(size_t(kMax_) + 1, 0.0), samples(size_t(kMax_) + 1, 0.0);
    double slabSeconds = 0, slabSamples = 0;
    for (size_t ti = t0; ti < t1; ++ti) {
        seconds[size_t(tasks[ti].k)] += taskSeconds[ti];
        samples[size_t(tasks[ti].k)] += tasks[ti].n;
        slabSeconds += taskSeconds[ti];
        slabSamples += tasks[ti].n;
    }
    if (!(slabSeconds > 0)) return 1.0;
    const double all = slabSeconds / slabSamples;
    double chains = 0;
    for (int k = lo_; k <= hi_; ++k) chains += chainShare_[size_t(k)] * (samples[size_t(k)] > 0 ? seconds[size_t(k)] / samples[size_t(k)] : all);
    return chains / all;
}

// Each length's share of the chains the pools `p` predict: b_k / sum b (the allocation's
// rule), alike where no pool has light yet.
std::vector<double> MmltRender::shares(const std::vector<SamplePool>& p) const {
    std::vector<double> s(size_t(kMax_) + 1, 0.0);
    double sum = 0;
    for (int k = lo_; k <= hi_; ++k) sum += p[size_t(k)].mean();
    for (int k = lo_; k <= hi_; ++k) s[size_t(k)] = sum > 0 ? p[size_t(k)].mean() / sum : 1.0 / double(hi_ - lo_ + 1);
    return s;
}

// The first pool: two batches, the bootstrap's even and odd chunks, each weighed by the
// share of the chains the other one predicts for the length (poolWeights: cross-fitted, so
// that no batch's weight follows its own values).
void MmltRender::closeBootstrap(std::vector<SamplePool>& even, std::vector<SamplePool>& odd) {
    const std::vector<double> fromEven = shares(even), fromOdd = shares(odd);
    for (int k = lo_; k <= hi_; ++k) {
        SamplePool& pool = pools_[size_t(k)];
        pool.clear();
        pool.addBatch(even[size_t(k)], 0, fromOdd[size_t(k)]);
        pool.addBatch(odd[size_t(k)], 0, fromEven[size_t(k)]);
    }
    batchLarge_.assign(2, 0);
    weighPools();
}

// Every pool's batches weighed anew for the batches it now holds (poolWeights).
void MmltRender::weighPools() {
    for (int k = lo_; k <= hi_; ++k) pools_[size_t(k)].weigh(poolWeights(pools_[size_t(k)].batches, batchLarge_, 2));
}

namespace {

// Pool entries as bytes for an exchange between ranks, and back.
void appendPool(std::vector<uint8_t>& out, const SamplePool& p) {
    const uint64_t head[3] = {p.count, uint64_t(p.lit.size()), 0};
    const size_t at = out.size();
    out.resize(at + sizeof head + sizeof(double) + p.lit.size() * sizeof(PoolEntry));
    std::memcpy(&out[at], head, sizeof head);
    std::memcpy(&out[at + sizeof head], &p.sumWC, sizeof(double));
    if (!p.lit.empty()) std::memcpy(&out[at + sizeof head + sizeof(double)], p.lit.data(), p.lit.size() * sizeof(PoolEntry));
}

const uint8_t* readPool(const uint8_t* in, SamplePool& p) {
    uint64_t head[3];
    std::memcpy(head, in, sizeof head);
    in += sizeof head;
    p.count = head[0];
    std::memcpy(&p.sumWC, in, sizeof(double));
    in += sizeof(double);
    p.lit.resize(size_t(head[1]));
    if (!p.lit.empty()) std::memcpy(p.lit.data(), in, p.lit.size() * sizeof(PoolEntry));
    return in + p.lit.size() * sizeof(PoolEntry);
}

}  // namespace

// Split across ranks: this rank filled pools [first, first + count) (its contiguous share);
// afterwards every rank holds all of them, in order (rank order is task order).
void MmltRender::exchangePools(std::vector<SamplePool>& pools, size_t first, size_t count) {
    if (!ranks_) return;
    std::vector<uint8_t> mine;
    for (size_t i = first; i < first + count; ++i) appendPool(mine, pools[i]);
    std::vector<size_t> sizes;
    const std::vector<uint8_t> all = ranks_->allGather(mine.data(), mine.size(), sizes);
    const uint8_t* in = all.data();
    for (int r = 0; r < ranks_->size(); ++r) {
        const auto [a, b] = shareOf(ranks_->size(), r, pools.size());
        for (size_t i = a; i < b; ++i) in = readPool(in, pools[i]);
    }
}

// A hash of every pool (counts, sums, entries) at the start of a pass: the same on every
// rank, and the same as one process's (RenderStats::Mmlt::poolDigestByRank).
void MmltRender::mergeDigest() {
    uint64_t h = poolDigest_;
    auto mix = [&](uint64_t x) { h = mix64(h ^ x) + 0x9e3779b97f4a7c15ull; };
    for (const SamplePool& p : pools_) {
        uint64_t sum = 0;
        std::memcpy(&sum, &p.sumWC, sizeof sum);
        mix(p.count);
        mix(sum);
        for (const PoolBatch& b : p.batches) mix(b.count);
        for (const PoolEntry& e : p.lit) {
            uint32_t c = 0, w = 0;
            std::memcpy(&c, &e.c, sizeof c);
            std::memcpy(&w, &e.w, sizeof w);
            mix(e.key);
            mix(uint64_t(c) << 32 | w);
            mix(e.batch);
        }
    }
    poolDigest_ = h;
}
}  // namespace wmlt::mmlt_detail

namespace wmlt {

// Weights alpha_b of a length's batches 0..p-1 (the pool of pass p - 1), summing to 1, each
// decided by nothing in its own batch, so that sum_b alpha_b mean_b is an unbiased b_k for
// any split of the batches among the lengths (SamplePool). The first `cross` batches (the
// bootstrap's halves) weigh n_b / (n + M_b): n their samples together, M_b the samples the
// later batches hold as batch b predicts them (its share s_b, from the other half's means, of
// each later batch's large steps, plus that batch's fresh samples of the length; fixed
// before the later batches are drawn, and independent of batch b's own values). The rest
// R = 1 - sum alpha goes to the later batches by stick-breaking (alpha_b = g_b R_b,
// R_{b+1} = (1 - g_b) R_b), g_b = n_b / (n_b + M_b) with s_b the batch's own share of its
// large steps (the allocation its chains had, which the next ones roughly keep), and the
// last batch with samples takes what is left (g = 1). g_b and R_b are fixed before batch b
// is drawn (its count is not a value), so E[alpha_b mean_b] = b_k E[alpha_b]. Where the
// predictions hold, alpha_b is n_b / sum n, the plain mean; where they fail, the estimate
// stays unbiased and only its variance grows.
std::vector<double> poolWeights(const std::vector<PoolBatch>& batches, const std::vector<uint64_t>& large, size_t cross) {
    const size_t p = batches.size();
    std::vector<double> alpha(p, 0.0);
    size_t last = p;  // the last batch with samples
    while (last > 0 && batches[last - 1].count == 0) --last;
    if (last == 0) return alpha;
    auto later = [&](size_t b, size_t from) {  // M_b over the batches from..last-1
        double m = 0;
        for (size_t i = from; i < last; ++i) m += batches[b].share * double(large[i]) + double(batches[i].fresh);
        return m;
    };
    const size_t group = std::min(cross, p);
    double n = 0, rest = 1;
    for (size_t b = 0; b < group; ++b) n += double(batches[b].count);
    for (size_t b = 0; b < group; ++b) {
        alpha[b] = n > 0 ? double(batches[b].count) / (n + later(b, group)) : 0.0;
        rest -= alpha[b];
    }
    for (size_t b = group; b < last; ++b) {
        const double nb = double(batches[b].count);
        const double g = b + 1 >= last ? 1.0 : nb > 0 ? nb / (nb + later(b, b + 1)) : 0.0;
        alpha[b] = g * rest;
        rest -= alpha[b];
    }
    return alpha;
}

// thinPool's tau: with the v = w c in decreasing order and f(m) = (the sum of all but the
// m largest) / (keep - m), tau = f(m) for the least m with v_(m) < f(m) (the m largest are
// kept whole, the rest share keep - m places). Removing values >= f(m) lowers the level
// (f(m') <= f(m)), so from m = 0 the count of values >= f(m) grows to that m and stays: a
// few passes over the pool instead of a sort (which was 2% of an MMLT render of the
// Cornell box at 128 mutations per pixel). above >= keep happens only by rounding (lit
// entries have v > 0, so the level stays above keep - m values).
double thinningThreshold(const std::vector<PoolEntry>& e, size_t keep) {
    double tau = 0;
    for (const PoolEntry& x : e) tau += double(x.w) * double(x.c);
    tau /= double(keep);
    for (size_t m = 0;;) {
        size_t above = 0;
        double rest = 0;
        for (const PoolEntry& x : e) {
            const double vx = double(x.w) * double(x.c);
            if (vx >= tau) ++above;
            else rest += vx;
        }
        if (above == m || above >= keep) return tau;
        m = above;
        tau = rest / double(keep - m);
    }
}

void thinPool(SamplePool& pool, size_t keep, uint64_t seed, uint32_t round) {
    std::vector<PoolEntry>& e = pool.lit;
    if (e.size() <= keep || keep == 0) return;
    // tau with sum_i min(1, v_i / tau) = keep, v_i = w_i c_i: the entries above tau are kept
    // as they are; the others by a systematic comb over their v / tau (one random offset):
    // each is kept with probability v_i / tau and then weighs tau / c_i, and the comb keeps
    // their total within tau of what it was (independent draws would add a variance of
    // about tau times their total).
    const double tau = thinningThreshold(e, keep);
    double comb = double(sampleDimension(mix64(seed ^ 0x5448494eu /* "THIN" */), round));
    size_t n = 0;
    double sum = 0;
    for (const PoolEntry& x : e) {
        PoolEntry y = x;
        const double vx = double(x.w) * double(x.c);
        if (vx < tau) {
            comb -= vx / tau;
            if (comb >= 0) continue;
            comb += 1;
            y.w = float(tau / double(x.c));
        }
        sum += double(y.w) * double(y.c);
        e[n++] = y;
    }
    e.resize(n);
    pool.sumWC = sum;
}

}  // namespace wmlt
