// MMLT's pools (mmlt_render.h): the bootstrap, tracing fresh samples of every length, and,
// split across ranks, exchanging every task's pool samples so that every rank merges the
// same pools.
#include "stages/mmlt/mmlt_render.h"

namespace wmlt::mmlt_detail {

// Fresh samples [from, to[k]) of every length k (pass pass_) into the pools, in parallel
// tasks merged in task order. The bootstrap under a time budget stops early once it has spent
// 5% of the budget; false when it was stopped (by the budget or a cancel, as all ranks agree).
bool MmltRender::tracePool(uint32_t from, const std::vector<uint32_t>& to, bool bootstrap) {
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
        const auto [t0, t1] = shareOf(ranks_, tasks.size());  // this rank's tasks
        tbb::parallel_for(t0, t1, [&](size_t ti) {
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
        });
        exchangePools(out, t0, t1 - t0);
        if (!brightness_.empty()) exchangePools(outMap, t0, t1 - t0);
        for (size_t ti = 0; ti < tasks.size(); ++ti) {
            pools_[size_t(tasks[ti].k)].add(out[ti]);
            collectBrightness(outMap[ti], tasks[ti].k);
            counters_.nonfinite += nonfinite[ti];
        }
        done += slab;
        sampleSeconds_ = (elapsed() - start) / double(samples);
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
// samples of every length, then each length gets its share of the whole in proportion to
// its b_k as the probe estimates it (its share of the chains and of the mutations: where
// the seeds are needed), at least 256. The whole is 5% of the mutations asked for or two
// per chain, whichever is more, so the bootstrap is spread over the lengths as the
// mutations are and costs about 5% of them (an equal count per length spent most of it on
// the long lengths, whose samples cost the most and which get few chains). The probe's
// samples join the second pass's pools, not the first: the first pool's size then depends
// on the probe only, not on its own values, and its mean stays unbiased. Under a time
// budget tracePool stops the bootstrap at 5% of the budget (if that is in the probe, the
// probe is the first pool). --bootstrap N: N samples of every length, in one step.
void MmltRender::bootstrap() {
    const int nLengths = hi_ - lo_ + 1;
    const double whole = timed() ? double(1 << 20) * nLengths : std::max(0.05 * targetMutations_, 2.0 * chains_);
    const bool fixed = opt_.bootstrap > 0;
    const uint32_t probe = fixed ? uint32_t(opt_.bootstrap) : kBatchChains;
    std::vector<uint32_t> to(size_t(kMax_) + 1, probe);
    if (!tracePool(0, to, true) || fixed) return;
    double sum = 0;
    for (int k = lo_; k <= hi_; ++k) sum += pools_[size_t(k)].mean();
    for (int k = lo_; k <= hi_; ++k) {
        const double share = sum > 0 ? pools_[size_t(k)].mean() / sum : 1.0 / nLengths;  // no light yet: alike
        to[size_t(k)] = probe + uint32_t(std::clamp(std::ceil(whole * share), double(probe), double(1 << 20)));
        std::swap(pools_[size_t(k)], next_[size_t(k)]);  // the probe: the second pass's
    }
    tracePool(probe, to, true);
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
        for (const PoolEntry& e : p.lit) {
            uint32_t c = 0, w = 0;
            std::memcpy(&c, &e.c, sizeof c);
            std::memcpy(&w, &e.w, sizeof w);
            mix(e.key);
            mix(uint64_t(c) << 32 | w);
        }
    }
    poolDigest_ = h;
}
}  // namespace wmlt::mmlt_detail
