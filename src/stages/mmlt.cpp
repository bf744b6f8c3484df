// The MMLT driver (mmlt.md; docs/mmlt-chains.md for the many-chain design and the
// measurements that chose it). The render is a sequence of passes; each pass:
//  1. tracePool: the pool of every length k is a set of independent uniform samples of u:
//     the bootstrap in the first pass, then fresh samples and the previous pass's
//     large-step proposals (each an independent uniform sample, its key kept);
//     b_k,p = the pool's mean c;
//  2. allocateChains: the C chains go to the lengths whose pool has light in proportion to
//     b_k (the mean of all pools so far), by largest remainders, never at random, at least
//     one each;
//  3. seedChains: each chain starts at a pool sample chosen in proportion to c (systematic
//     resampling) and replays it: the replay must give the same c bit for bit;
//  4. runRounds: passLength iterations of every chain (mutate, evaluate, accept and splat),
//     in rounds of batches run in parallel; each splat carries the weight
//     b_k,p / chains_k,p of its length and pass.
// A chain started from a pool by resampling in proportion to c and weighted by the pool's
// mean c gives an unbiased estimate after any number of steps (importance resampling: the
// pair (pool, start) has the target as its weighted marginal, and the Metropolis kernel
// keeps it), so every pass is unbiased whatever its length and its chains' count, and so is
// their average weighted by iterations: I = pixels * film / (iterations per chain).
// One film serves every length. Splats are kept per batch and added in batch order after
// each round, pools likewise: a seed and any thread count give one image.
// Split across ranks (RenderOptions::ranks, docs/mpi.md): each rank runs a contiguous share
// of the pool tasks and of the batches; after each exchange every rank holds every task's
// pool samples in task order and merges them as one process does, so the pools, b_k, the
// allocation and the seeds are the same on every rank and the same as one process's; rank
// 0 makes every decision that depends on the clock; the films are summed on rank 0.
#include "stages/mmlt.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <unordered_set>

#include "stages/distributed_films.h"
#include "stages/film.h"
#include "stages/memory.h"
#include "stages/mmlt_stages.h"
#include "stages/passes.h"
#include "stages/preview.h"
#include "wavemmlt/error.h"

namespace wmlt {

namespace {

constexpr uint32_t kBatchChains = 256;      // chains per batch: the tasks of a round
constexpr double kProposalsPerRound = 1 << 18;  // bounds the splat lists (~8 MB) and a round's time

using Clock = std::chrono::steady_clock;

uint32_t slotsIn(const std::vector<BatchSlice>& b) { return b.empty() ? 0 : b.back().slot0 + b.back().n; }

// One pool-tracing task: samples [i0, i0 + n) of length k.
struct PoolTask {
    int k;
    uint32_t i0, n;
};

class MmltRender {
public:
    MmltRender(const Scene& scene, const RenderOptions& opt);
    RenderResult run();

private:
    void tracePool(uint32_t perLength, bool bootstrap);
    bool allocateChains();
    void seedChains();
    void planBatches();
    void replaySeeds();
    void runRounds(uint64_t passEnd);
    RenderResult resolve();
    // Render time: paused time (a viewer's) is left out.
    double elapsed() const { return std::chrono::duration<double>(Clock::now() - t0_).count() - paused_; }
    Image image() const;
    bool timed() const { return opt_.timeBudget > 0; }
    bool stopRequested() const { return opt_.cancel && opt_.cancel->load(); }
    // Split across ranks: rank 0's decision `rootValue` and whether any rank was cancelled
    // (one exchange; without ranks, this process's flag).
    Agreement agreeAtBoundary(uint64_t rootValue) {
        const Agreement a = agree(ranks_, false, stopRequested(), rootValue);
        cancelled_ = cancelled_ || a.cancel;
        return a;
    }
    void exchangePools(std::vector<SamplePool>& pools, size_t first, size_t count);
    void sumAcrossRanks(RenderResult& res);
    void mergeDigest();
    // Entries the pool of length k may hold before it is thinned to half: 8 per chain of
    // the length (its last allocation; an equal share before the first), at least 2^13.
    size_t poolCapacity(int k) const {
        const size_t n = stats_.passes ? stats_.chains[size_t(k)] : chains_ / size_t(kMax_ - kMin_ + 1);
        return std::max<size_t>(size_t(1) << 13, 8 * n);
    }
    void thin(SamplePool& pool, int k) {
        if (pool.lit.size() > poolCapacity(k)) thinPool(pool, poolCapacity(k) / 2, opt_.seed, thinRounds_++);
    }

    const Scene& scene_;
    const RenderOptions& opt_;
    Distributed* ranks_;                   // nullptr: one process
    bool cancelled_ = false;               // agreed by the ranks at a boundary
    uint64_t poolDigest_ = 0;              // a hash of the pools of every pass
    Clock::time_point t0_;
    int kMin_, kMax_;
    double pixels_, targetMutations_;
    uint32_t chains_ = 1;                  // C
    uint64_t target_ = 0;                  // iterations per chain (spp renders)
    uint32_t passLength_ = 1;
    uint32_t pass_ = 0;
    uint64_t iteration_ = 0;               // iterations of every chain so far
    double passWeight_ = 1;                // f_p of this pass (allocateChains)
    double weighted_ = 0;                  // sum over rounds of f_p times iterations: the image's divisor
    bool stopped_ = false;
    double paused_ = 0;                    // seconds a viewer held the render between rounds
    double perIteration_ = 0;              // seconds per iteration of all chains, measured
    double sampleSeconds_ = 0;             // seconds per pool sample, measured

    tbb::enumerable_thread_specific<MmltBatch> batches_;
    tbb::enumerable_thread_specific<PtCounters> rays_;
    std::vector<SamplePool> pools_, next_;  // [k]: this pass's pool, the next one's large steps
    std::vector<double> passB_;            // sum over rounds of iterations times b_k
    uint32_t thinRounds_ = 0;
    std::vector<ChainGroup> groups_;       // this pass's chains, one group per length with chains
    std::vector<std::vector<BatchSlice>> plan_;  // per batch: its slices
    SplatFilm film_;
    std::vector<SplatFilm> lengthFilms_;   // RenderOptions::lengthImages only
    RenderStats::Mmlt stats_;
    MmltCounters counters_;
    double ratioSum_ = 0;
    uint64_t rounds_ = 0;
    size_t poolEntries_ = 0;               // the most pool entries held at once
};

MmltRender::MmltRender(const Scene& scene, const RenderOptions& opt)
    : scene_(scene), opt_(opt), ranks_(opt.ranks && opt.ranks->many() ? opt.ranks : nullptr), t0_(Clock::now()), kMin_(std::max(1, opt.minPathLength)), kMax_(opt.maxPathLength),
      batches_([maxLength = opt.maxPathLength] {
          MmltBatch mb;
          mb.reserve(kBatchChains + size_t(maxLength) + 1, maxLength);
          return mb;
      }),
      film_(scene.camera.width, scene.camera.height) {
    pixels_ = double(scene.camera.width) * double(scene.camera.height);
    targetMutations_ = double(opt.spp) * pixels_;
    // No more chains than mutations asked for (a small image at few mutations per pixel).
    const double asked = timed() ? double(opt.chains) : std::min(double(opt.chains), targetMutations_);
    chains_ = uint32_t(std::max(1.0, asked));
    target_ = uint64_t(std::ceil(targetMutations_ / double(chains_)));
    const size_t n = size_t(kMax_) + 1;
    pools_.resize(n);
    next_.resize(n);
    passB_.assign(n, 0.0);
    stats_.b.assign(n, 0.0);
    stats_.chains.assign(n, 0);
    for (auto* v : {&stats_.chainsSeeded, &stats_.distinctSeeds, &stats_.bootstrapNonzero, &stats_.poolSamples,
                    &stats_.proposals, &stats_.proposedSmall, &stats_.acceptedSmall, &stats_.proposedLarge,
                    &stats_.acceptedLarge})
        v->assign(n, 0);
    if (opt.lengthImages)
        for (size_t k = 0; k < n; ++k) lengthFilms_.emplace_back(scene.camera.width, scene.camera.height);
    // Memory, refused before anything large is allocated: the chain state at its largest
    // (every chain at MaxPathLength), the films, a round's splats.
    const double chainBytes = double(chains_) * double(mmltChainBytes(kMax_));
    const double filmBytes = 24.0 * pixels_ * double(1 + lengthFilms_.size());
    const double mem = physicalMemoryBytes();
    if (mem > 0 && chainBytes + filmBytes > 0.75 * mem)
        throw InputError("MMLT would need " + bytesText(chainBytes) + " of chain state and " + bytesText(filmBytes) +
                         " of films, more than 3/4 of this machine's " + bytesText(mem));
}

// Fresh samples [0, perLength) of every length (pass pass_) into the pools, in parallel
// tasks merged in task order. The bootstrap under a time budget stops early once it has spent
// 5% of the budget (at least 256 samples per length).
void MmltRender::tracePool(uint32_t perLength, bool bootstrap) {
    const uint32_t chunk = kBatchChains;
    uint32_t done = 0;
    // Under a time budget the bootstrap runs in slabs that grow while they are short (64
    // samples per length, then about 1% of the budget each), so that it can stop on time.
    // Otherwise a slab is about 4096 samples per thread (of every rank) in all lengths, so
    // that Ctrl-C is heard within a fraction of a second (mpirun kills the ranks about a
    // second after it); those slabs are whole tasks, so the pools do not depend on them
    // (each length's tasks are added in order, and their sums in the same tasks).
    const double workers = double(tbb::this_task_arena::max_concurrency()) * (ranks_ ? ranks_->size() : 1);
    uint32_t slabSize = bootstrap && timed()
        ? 64 : chunk * uint32_t(std::ceil(4096.0 * workers / double(kMax_ - kMin_ + 1) / double(chunk)));
    while (done < perLength) {
        const double start = elapsed();
        const uint32_t slab = std::min(perLength - done, slabSize);
        std::vector<PoolTask> tasks;
        for (int k = kMin_; k <= kMax_; ++k)
            for (uint32_t i = done; i < done + slab; i += chunk) tasks.push_back({k, i, std::min(chunk, done + slab - i)});
        std::vector<SamplePool> out(tasks.size());
        std::vector<uint64_t> nonfinite(tasks.size(), 0);
        const auto [t0, t1] = shareOf(ranks_, tasks.size());  // this rank's tasks
        tbb::parallel_for(t0, t1, [&](size_t ti) {
            const PoolTask& t = tasks[ti];
            MmltBatch& mb = batches_.local();
            mb.counters.nonfinite = 0;
            fillPoolRows(mb, t.k, pass_, t.i0, t.n, opt_.seed);
            evaluateProposals(scene_, mb, opt_.misBeta, rays_.local());
            for (uint32_t i = 0; i < t.n; ++i) {
                const Vec3 F = contributionOf(mb, i);
                const float c = targetOf(F);
                if (c == 0.0f && !(isFinite(F) && std::isfinite(luminance(F)))) ++mb.counters.nonfinite;
                out[ti].sumWC += double(c);
                if (c > 0) out[ti].lit.push_back({mb.bpt.key[i], c, 1.0f, F, mb.bpt.pixel[i]});
            }
            out[ti].count = t.n;
            nonfinite[ti] = mb.counters.nonfinite;
        });
        exchangePools(out, t0, t1 - t0);
        for (size_t ti = 0; ti < tasks.size(); ++ti) {
            pools_[size_t(tasks[ti].k)].add(out[ti]);
            counters_.nonfinite += nonfinite[ti];
        }
        done += slab;
        sampleSeconds_ = (elapsed() - start) / (double(slab) * (kMax_ - kMin_ + 1));
        // The next slab, rank 0's figure (0: the timed bootstrap has spent its 5%).
        uint64_t next = slabSize;
        if (bootstrap && timed()) {
            const double perSlab = 0.01 * opt_.timeBudget / (sampleSeconds_ * (kMax_ - kMin_ + 1));
            next = elapsed() >= 0.05 * opt_.timeBudget ? 0 : uint64_t(std::clamp(perSlab, 64.0, double(1 << 16)));
        }
        const Agreement a = agreeAtBoundary(next);
        if (a.value == 0 || a.cancel) break;
        slabSize = uint32_t(a.value);
    }
    if (bootstrap) stats_.bootstrapSamples = done;
}

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

// Chains per length: C b_k / sum b by largest remainders over the lengths whose pool has
// light (b_k: the pool's mean), then at least 1 for each such length (taken from the
// largest allocation while it has more than one). False when no pool has light.
bool MmltRender::allocateChains() {
    std::vector<double> b(size_t(kMax_) + 1, 0.0);
    double sum = 0;
    for (int k = kMin_; k <= kMax_; ++k) {
        stats_.poolSamples[size_t(k)] = pools_[size_t(k)].count;
        if (pools_[size_t(k)].lit.empty()) continue;
        b[size_t(k)] = pools_[size_t(k)].mean();
        sum += b[size_t(k)];
    }
    groups_.clear();
    // A pass's weight f_p = N / (N + rho C), N the pool's samples (a count, independent of
    // their values: the weighted average of the passes stays unbiased): a pass whose pool
    // is small next to its chains mostly repeats its few seeds, and counts less. rho = 32
    // against rho = 0 (every iteration alike), 16 s renders: 7% lower RMSE on the seed room
    // at 1024 and at 65536 chains, the Cornell box unchanged (docs/mmlt-chains.md).
    constexpr double rho = 32;
    uint64_t poolSamples = 0;
    for (int k = kMin_; k <= kMax_; ++k) poolSamples += pools_[size_t(k)].count;
    passWeight_ = double(poolSamples) / (double(poolSamples) + rho * double(chains_));
    if (!(sum > 0)) return false;
    std::vector<uint32_t> n(b.size(), 0);
    std::vector<std::pair<double, size_t>> rem;
    uint32_t given = 0;
    for (size_t k = 0; k < b.size(); ++k) {
        const double share = double(chains_) * b[k] / sum;
        n[k] = uint32_t(std::floor(share));
        given += n[k];
        rem.push_back({share - std::floor(share), k});
    }
    std::stable_sort(rem.begin(), rem.end(), [](auto& a, auto& c) { return a.first > c.first; });
    for (size_t i = 0; given < chains_ && i < rem.size(); ++i, ++given) ++n[rem[i].second];
    for (size_t k = 0; k < b.size(); ++k) {
        if (!(b[k] > 0) || n[k] > 0) continue;
        const size_t big = size_t(std::max_element(n.begin(), n.end()) - n.begin());
        if (n[big] > 1) --n[big];
        n[k] = 1;
    }
    uint32_t first = 0;
    for (int k = kMin_; k <= kMax_; ++k) {
        stats_.chains[size_t(k)] = n[size_t(k)];
        if (!n[size_t(k)]) continue;
        ChainGroup g;
        g.k = k;
        g.first = first;
        g.dims = StrategyLayout::size(k);
        g.weight = float(passWeight_ * pools_[size_t(k)].mean() / double(n[size_t(k)]));
        first += n[size_t(k)];
        groups_.push_back(std::move(g));
        groups_.back().resize(n[size_t(k)]);
    }
    return true;
}

// Systematic resampling of each group's chains from its pool in proportion to c, and the
// replay of every seed (its c must come back bit for bit).
void MmltRender::seedChains() {
    uint64_t bytes = 0;
    for (ChainGroup& g : groups_) {
        const SamplePool& pool = pools_[size_t(g.k)];
        double total = 0;
        for (const PoolEntry& e : pool.lit) total += double(e.w) * double(e.c);
        const double offset = double(sampleDimension(mmltPoolKey(opt_.seed, pass_, g.k, 0xffffffffu), 0));
        std::unordered_set<uint64_t> distinct;
        size_t e = 0;
        double cum = double(pool.lit[0].w) * double(pool.lit[0].c);
        for (uint32_t c = 0; c < g.count; ++c) {
            const double x = (double(c) + offset) / double(g.count) * total;
            while (cum <= x && e + 1 < pool.lit.size()) {
                ++e;
                cum += double(pool.lit[e].w) * double(pool.lit[e].c);
            }
            const PoolEntry& entry = pool.lit[e];
            g.seed[c] = entry.key;
            g.F[c] = entry.F;
            g.c[c] = entry.c;
            g.pixel[c] = entry.pixel;
            distinct.insert(g.seed[c]);
            for (uint32_t d = 0; d < g.dims; ++d) g.value[size_t(d) * g.count + c] = poolCoordinate(g.seed[c], d);
        }
        stats_.chainsSeeded[size_t(g.k)] += g.count;
        stats_.distinctSeeds[size_t(g.k)] += distinct.size();
        bytes += uint64_t(g.count) * mmltChainBytes(g.k);
    }
    stats_.chainBytes = std::max(stats_.chainBytes, bytes);
    planBatches();
    mergeDigest();
    replaySeeds();
}

// Replays seeds (every one in the first pass, one in kReplayShare of them by their key's
// hash after that): the evaluation of the seed's u must give its pool entry's F, c and
// pixel bit for bit, or the estimator would be wrong (counted in mmlt_replay_mismatches).
void MmltRender::replaySeeds() {
    constexpr uint64_t kReplayShare = 8;
    std::vector<std::vector<BatchSlice>> plan(1);
    for (size_t gi = 0; gi < groups_.size(); ++gi)
        for (uint32_t c = 0; c < groups_[gi].count; ++c) {
            if (pass_ > 0 && mix64(groups_[gi].seed[c]) % kReplayShare != 0) continue;
            if (slotsIn(plan.back()) >= kBatchChains) plan.emplace_back();
            std::vector<BatchSlice>& b = plan.back();
            if (!b.empty() && b.back().group == int(gi) && b.back().c0 + b.back().n == c) ++b.back().n;
            else b.push_back({int(gi), c, 1, slotsIn(b)});
        }
    std::vector<uint64_t> mismatches(plan.size(), 0);
    const auto [p0, p1] = shareOf(ranks_, plan.size());  // this rank's share of the replays
    tbb::parallel_for(p0, p1, [&](size_t ti) {
        MmltBatch& mb = batches_.local();
        mb.slices = plan[ti];
        fillSeedRows(groups_, mb);
        evaluateProposals(scene_, mb, opt_.misBeta, rays_.local());
        for (const BatchSlice& sl : mb.slices) {
            const ChainGroup& g = groups_[size_t(sl.group)];
            for (uint32_t j = 0; j < sl.n; ++j) {
                const uint32_t i = sl.slot0 + j, c = sl.c0 + j;
                const Vec3 F = contributionOf(mb, i);
                const float cc = targetOf(F);
                if (std::memcmp(&cc, &g.c[c], sizeof cc) != 0 || std::memcmp(&F, &g.F[c], sizeof F) != 0 ||
                    mb.bpt.pixel[i] != g.pixel[c])
                    ++mismatches[ti];
            }
        }
    });
    for (uint64_t m : mismatches) stats_.replayMismatches += m;
    for (size_t ti = p0; ti < p1; ++ti) stats_.replayed += slotsIn(plan[ti]);
}

// Batch j holds chains [C_k j / B, C_k (j + 1) / B) of every length: each batch a share of
// every length, so that batches cost about the same whatever the lengths' split.
void MmltRender::planBatches() {
    const uint32_t B = (chains_ + kBatchChains - 1) / kBatchChains;
    plan_.assign(B, {});
    for (uint32_t j = 0; j < B; ++j) {
        uint32_t slot = 0;
        for (size_t gi = 0; gi < groups_.size(); ++gi) {
            const uint64_t n = groups_[gi].count;
            const uint32_t c0 = uint32_t(n * j / B), c1 = uint32_t(n * (j + 1) / B);
            if (c1 > c0) plan_[j].push_back({int(gi), c0, c1 - c0, slot});
            slot += c1 - c0;
        }
    }
    stats_.tasksPerRound = B;
}

struct TaskOutput {
    std::vector<Splat> splats;
    std::vector<uint8_t> splatLength;
    std::vector<SamplePool> pools;
    MmltCounters counters;
    double seconds = 0;
};

// Rounds of iterations until the pass ends at iteration passEnd (or the render does).
void MmltRender::runRounds(uint64_t passEnd) {
    std::vector<TaskOutput> outputs(plan_.size());
    const uint32_t perRound = uint32_t(std::clamp(kProposalsPerRound / chains_, 1.0, 4096.0));
    const auto [b0, b1] = shareOf(ranks_, plan_.size());  // this rank's batches
    const size_t nk = size_t(kMax_) + 1;
    std::vector<SamplePool> roundPools;  // split across ranks: [batch * nk + k], every batch's
    while (iteration_ < passEnd) {
        // The round's iterations r (rank 0 decides; 0: the time is spent).
        uint32_t r = uint32_t(std::min<uint64_t>(perRound, passEnd - iteration_));
        if (timed()) {  // a time budget: the last rounds shrink so as to end on time
            const double left = opt_.timeBudget - elapsed();
            r = left <= 0.5 * perIteration_ && iteration_ > 0 ? 0
                : perIteration_ > 0 ? uint32_t(std::clamp(std::floor(left / perIteration_ + 0.5), 1.0, double(r))) : 1;
        }
        const Agreement a = agreeAtBoundary(r);
        r = uint32_t(a.value);
        // Ctrl-C ends the render after this round; but the first round always runs (one
        // iteration), so that a render stopped during its bootstrap still has an image.
        if (a.cancel) {
            if (iteration_ > 0) { stopped_ = true; return; }
            r = std::min<uint32_t>(r, 1);
        }
        if (r == 0) { stopped_ = true; return; }
        const double roundStart = elapsed();
        tbb::parallel_for(b0, b1, [&](size_t ti) {
            const auto start = Clock::now();
            MmltBatch& mb = batches_.local();
            mb.slices = plan_[ti];
            mb.splats.clear();
            mb.splatLength.clear();
            for (SamplePool& p : mb.pools) p.clear();
            mb.counters = MmltCounters();
            for (uint64_t n = iteration_; n < iteration_ + r; ++n) {
                mutateChains(groups_, mb, opt_.seed, uint32_t(n), opt_.probLarge);
                evaluateProposals(scene_, mb, opt_.misBeta, rays_.local());
                acceptAndSplat(groups_, mb);
            }
            TaskOutput& o = outputs[ti];
            o.splats.swap(mb.splats);
            o.splatLength.swap(mb.splatLength);
            o.pools.swap(mb.pools);
            mb.pools.resize(size_t(kMax_) + 1);
            o.counters = mb.counters;
            o.seconds = std::chrono::duration<double>(Clock::now() - start).count();
        });
        if (ranks_) {  // every batch's large steps on every rank, in batch order
            roundPools.assign(plan_.size() * nk, SamplePool());
            for (size_t ti = b0; ti < b1; ++ti)
                for (size_t k = 0; k < nk; ++k) roundPools[ti * nk + k] = std::move(outputs[ti].pools[k]);
            exchangePools(roundPools, b0 * nk, (b1 - b0) * nk);
        }
        double longest = 0, sum = 0;
        for (size_t ti = 0; ti < outputs.size(); ++ti) {  // in batch order: deterministic
            TaskOutput& o = outputs[ti];
            for (size_t i = 0; i < o.splats.size(); ++i) {
                film_.add(o.splats[i]);
                if (!lengthFilms_.empty()) lengthFilms_[o.splatLength[i]].add(o.splats[i]);
            }
            for (size_t k = 0; k < nk; ++k) {
                next_[k].add(ranks_ ? roundPools[ti * nk + k] : o.pools[k]);
                thin(next_[k], int(k));
            }
            counters_.add(o.counters);
            longest = std::max(longest, o.seconds);
            sum += o.seconds;
        }
        ratioSum_ += sum > 0 ? longest / (sum / double(b1 - b0)) : 1.0;
        ++rounds_;
        for (const ChainGroup& g : groups_) passB_[size_t(g.k)] += double(r) * double(g.weight) * g.count;
        weighted_ += double(r) * passWeight_;
        for (const ChainGroup& g : groups_) stats_.proposals[size_t(g.k)] += uint64_t(r) * g.count;
        iteration_ += r;
        perIteration_ = (elapsed() - roundStart) / r;
        const double fraction = timed() ? std::min(1.0, elapsed() / opt_.timeBudget) : double(iteration_) / double(target_);
        if (opt_.progress) opt_.progress(fraction);
        paused_ += offerSnapshot(opt_, [&] {
            return Snapshot{image(), fraction, elapsed(), uint64_t(double(iteration_) * chains_ / pixels_), raysSoFar(rays_)};
        });
    }
}

RenderResult MmltRender::run() {
    const int nLengths = kMax_ - kMin_ + 1;
    // The bootstrap: opt.bootstrap samples per length, or 5% of the mutations asked for or two
    // per chain, whichever is more (256 to 2^20 per length); under a time budget at most 5%
    // of it (tracePool stops it).
    const double autoBoot = timed() ? double(1 << 20) : std::max(0.05 * targetMutations_, 2.0 * chains_) / nLengths;
    const uint32_t nBoot =
        opt_.bootstrap > 0 ? uint32_t(opt_.bootstrap) : uint32_t(std::clamp(autoBoot, 256.0, double(1 << 20)));
    tracePool(nBoot, true);
    stats_.bBootstrap.assign(size_t(kMax_) + 1, 0.0);
    for (int k = kMin_; k <= kMax_; ++k) {
        stats_.bootstrapNonzero[size_t(k)] = pools_[size_t(k)].lit.size();
        stats_.bBootstrap[size_t(k)] = pools_[size_t(k)].mean();
        thin(pools_[size_t(k)], k);
    }
    // Under a time budget one iteration of all chains (about C samples) may cost at most 2%
    // of the budget, or the render could not end within it (--time 3 with 65536 chains on
    // a slow build): the chains are capped there, and --stats and a warning say so.
    stats_.chainsAsked = chains_;
    if (timed()) {  // rank 0's figure on every rank
        const double cap = std::floor(0.02 * opt_.timeBudget / std::max(sampleSeconds_, 1e-12));
        chains_ = uint32_t(agreeAtBoundary(uint64_t(std::clamp(cap, 1.0, double(chains_)))).value);
    }
    stats_.chainsRun = chains_;
    if (!allocateChains())
        throw InputError("no light reaches the camera: the bootstrap's " + std::to_string(stats_.bootstrapSamples) +
                         " samples of each path length " + std::to_string(kMin_) + ".." + std::to_string(kMax_) +
                         " all carry zero radiance (check the lights, MinPathLength and MaxPathLength)");
    // Iterations per pass: about 8 passes in a render, 32 to 1024 iterations each (each
    // pass replays its C seeds: 1 / passLength of the render at most).
    if (timed()) {  // rank 0's figure on every rank
        const double left = std::max(0.0, opt_.timeBudget - elapsed());
        target_ = agreeAtBoundary(uint64_t(left / std::max(sampleSeconds_, 1e-12) / double(chains_))).value;
    }
    passLength_ = opt_.passLength > 0 ? uint32_t(opt_.passLength)
                                      : uint32_t(std::clamp(double(target_) / 8.0, 32.0, 1024.0));
    // Fresh samples per length and pass (the large steps feed the pools too; the fresh ones
    // keep probing every length, with chains or not): C / 8 in all, at least 64 per length.
    const uint32_t fresh = std::max<uint32_t>(64, chains_ / (8 * uint32_t(nLengths)));
    double restartSeconds = 0;  // the last pass's start: pool, allocation, seeding and replay
    while (true) {
        const double passStart = elapsed();
        if (pass_ > 0) {
            // Rank 0 decides: a new pass (0), the end (1), or, with too little time left for a
            // restart to pay, the chains go on to the end (2; a pass may be any length: it
            // stays unbiased).
            enum : uint64_t { kNewPass, kEnd, kGoOn };
            uint64_t next = kNewPass;
            if (!timed() && iteration_ >= target_) next = kEnd;
            if (timed()) {
                const double left = opt_.timeBudget - elapsed();
                next = left <= 0.5 * perIteration_ ? kEnd : left < 2 * restartSeconds + perIteration_ ? kGoOn : kNewPass;
            }
            const Agreement a = agreeAtBoundary(next);
            if (a.cancel || a.value == kEnd) break;
            if (a.value == kGoOn) {
                runRounds(std::numeric_limits<uint64_t>::max());
                break;
            }
            tracePool(fresh, false);
            for (int k = kMin_; k <= kMax_; ++k) {
                pools_[size_t(k)].add(next_[size_t(k)]);
                next_[size_t(k)].clear();
                thin(pools_[size_t(k)], k);
            }
            if (!allocateChains()) {  // no light in any pool: the pass's estimate is 0
                iteration_ += passLength_;
                weighted_ += double(passLength_) * passWeight_;
                ++pass_;
                continue;
            }
        }
        size_t entries = 0;
        for (const SamplePool& p : pools_) entries += p.lit.size();
        poolEntries_ = std::max(poolEntries_, entries);
        seedChains();
        restartSeconds = elapsed() - passStart;
        ++stats_.passes;
        const uint64_t end = timed() ? iteration_ + passLength_ : std::min<uint64_t>(target_, iteration_ + passLength_);
        runRounds(end);
        ++pass_;
        if (stopped_) break;
    }
    return resolve();
}

// The image so far: pixels * film / T, T the iterations per chain (each length's splats
// already weighted per pass). The final image and every snapshot (preview.h).
// Split across ranks: rank 0's image of the job (every rank calls it: the films are summed).
Image MmltRender::image() const {
    const double norm = weighted_ > 0 ? pixels_ / weighted_ : 0.0;
    Image im(scene_.camera.width, scene_.camera.height);
    withFilmOfJob(ranks_, film_, [&](const SplatFilm& film) {
        for (size_t i = 0; i < im.rgb.size(); ++i) im.rgb[i] = float(film.sum[i] * norm);
        return 0;
    });
    return im;
}

// Split across ranks: the counters of every rank's batches summed on rank 0; b_k and the
// pools' digest as every rank has them (the test that they agree: test_mpi.cpp).
void MmltRender::sumAcrossRanks(RenderResult& res) {
    stats_.bByRank = {stats_.b};
    stats_.poolDigestByRank = {poolDigest_};
    if (!ranks_) return;
    std::vector<uint64_t> v(size_t(4 * (kMaxPathLength + 1) + 2));
    std::memcpy(v.data(), counters_.proposed, sizeof counters_.proposed);
    std::memcpy(v.data() + 2 * (kMaxPathLength + 1), counters_.accepted, sizeof counters_.accepted);
    v[v.size() - 2] = stats_.replayed;
    v[v.size() - 1] = stats_.replayMismatches;
    ranks_->sumToRoot(v.data(), v.size());
    std::memcpy(counters_.proposed, v.data(), sizeof counters_.proposed);
    std::memcpy(counters_.accepted, v.data() + 2 * (kMaxPathLength + 1), sizeof counters_.accepted);
    stats_.replayed = v[v.size() - 2];
    stats_.replayMismatches = v[v.size() - 1];
    std::vector<uint8_t> mine(stats_.b.size() * sizeof(double) + sizeof poolDigest_);
    std::memcpy(mine.data(), stats_.b.data(), stats_.b.size() * sizeof(double));
    std::memcpy(mine.data() + stats_.b.size() * sizeof(double), &poolDigest_, sizeof poolDigest_);
    std::vector<size_t> sizes;
    const std::vector<uint8_t> all = ranks_->allGather(mine.data(), mine.size(), sizes);
    stats_.bByRank.assign(size_t(ranks_->size()), std::vector<double>(stats_.b.size()));
    stats_.poolDigestByRank.assign(size_t(ranks_->size()), 0);
    for (size_t r = 0; r < size_t(ranks_->size()); ++r) {
        const uint8_t* at = all.data() + r * mine.size();
        std::memcpy(stats_.bByRank[r].data(), at, stats_.b.size() * sizeof(double));
        std::memcpy(&stats_.poolDigestByRank[r], at + stats_.b.size() * sizeof(double), sizeof poolDigest_);
    }
}

// The image and the stats.
RenderResult MmltRender::resolve() {
    PassResult pr;
    pr.seconds = elapsed();
    pr.completedSpp = uint32_t(double(iteration_) * chains_ / pixels_);
    pr.stopped = stopped_;
    pr.cancelled = cancelled_;
    pr.passes = rounds_;
    RenderResult res = startResult("mmlt", scene_, opt_, pr, rays_);
    stats_.iterations = iteration_;
    stats_.passLength = passLength_;
    stats_.longestTaskRatio = rounds_ ? ratioSum_ / double(rounds_) : 0.0;
    res.stats.samplesNonfiniteDiscarded = counters_.nonfinite;
    for (int k = kMin_; k <= kMax_; ++k) stats_.b[size_t(k)] = weighted_ > 0 ? passB_[size_t(k)] / weighted_ : 0.0;
    sumAcrossRanks(res);
    for (int k = kMin_; k <= kMax_; ++k) {
        stats_.proposedSmall[size_t(k)] = counters_.proposed[0][k];
        stats_.acceptedSmall[size_t(k)] = counters_.accepted[0][k];
        stats_.proposedLarge[size_t(k)] = counters_.proposed[1][k];
        stats_.acceptedLarge[size_t(k)] = counters_.accepted[1][k];
        stats_.mutations += stats_.proposals[size_t(k)];
    }
    res.stats.mmlt = stats_;
    res.stats.lengthMeanLuminance = stats_.b;
    const double norm = weighted_ > 0 ? pixels_ / weighted_ : 0.0;
    res.image = image();
    sumStatsToRoot(opt_.ranks, res.stats);  // rays, samples discarded, the exchanges' cost
    for (const SplatFilm& f : lengthFilms_) {
        res.lengthImages.emplace_back(f.width, f.height);
        for (size_t i = 0; i < f.sum.size(); ++i) res.lengthImages.back().rgb[i] = float(f.sum[i] * norm);
    }
    res.stats.buffers = {{"film", uint64_t(24 * pixels_)},
                         {"length films", uint64_t(24 * pixels_) * lengthFilms_.size()},
                         {"chain state", stats_.chainBytes},
                         {"pools", uint64_t(poolEntries_ * sizeof(PoolEntry))},
                         {"splat lists", uint64_t(kProposalsPerRound) * 2 * sizeof(Splat)}};
    return res;
}

}  // namespace

uint64_t mmltChainBytes(int k) { return uint64_t(StrategyLayout::size(k)) * 8 + 4 * 4 + 12 + 8; }

RenderResult renderMmlt(const Scene& scene, const RenderOptions& opt) { return MmltRender(scene, opt).run(); }

}  // namespace wmlt
