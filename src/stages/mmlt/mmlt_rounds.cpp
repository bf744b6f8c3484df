// MMLT's rounds (mmlt_render.h): a pass's iterations in rounds, each sized under the time
// budget (roundSize), run batch by batch in parallel (runBatch: mutate, evaluate, accept
// and splat), merged into the film and the next pools in batch order (mergeRound) and
// accounted (accountRound).
#include <tbb/global_control.h>

#include "stages/core/splat_passes.h"
#include "stages/mmlt/mmlt_render.h"

namespace wmlt::mmlt_detail {

// The film is merged in stripes of pixels, in parallel (from 4 threads on, runRounds): each
// task keeps its splats by stripe (MmltBatch::addSplat), and each stripe adds every task's
// in task order, so every pixel still gets its splats in one order whatever the threads.
// (The round's serial merge of splats and pools was 4.3% of its time on 2 threads on the
// Cornell box, the film half of it: on 64 cores a serial part of that size would take
// about half of a round.)
constexpr uint32_t kFilmStripes = MmltBatch::kStripes;

struct TaskOutput {
    std::vector<Splat> splats[kFilmStripes];
    std::vector<uint8_t> splatLength[kFilmStripes];
    std::vector<PointSplat> points[kFilmStripes];
    std::vector<uint8_t> pointLength[kFilmStripes];
    std::vector<SamplePool> pools, mapPools;  // [k]: the large steps for the pools, for the target map
    MmltCounters counters;
    double seconds = 0;
};

// The round's iterations r (rank 0 decides; 0: the render stops): at most perRound and the
// rest of the pass; under a time budget the last rounds shrink so as to end on time, each
// taking about half the time left, so that a machine that slows down during one (another
// process starts) overshoots by a part of that round, not by all of the time left. Ctrl-C
// ends the render after this round; but the first round always runs (one iteration), so
// that a render stopped during its bootstrap still has an image.
uint32_t MmltRender::roundSize(uint32_t perRound, uint64_t passEnd) {
    uint32_t r = uint32_t(std::min<uint64_t>(perRound, passEnd - iteration_));
    if (timed()) {
        const double left = opt_.timeBudget - elapsed();
        r = left <= 0.5 * perIteration_ && iteration_ > 0 ? 0
            : perIteration_ > 0                           ? uint32_t(std::clamp(std::floor(0.5 * left / perIteration_ + 0.5), 1.0, double(r)))
                                                          : 1;
    }
    const Agreement a = agreeAtBoundary(r);
    r = uint32_t(a.value);
    if (a.cancel) r = iteration_ > 0 ? 0 : std::min<uint32_t>(r, 1);
    return r;
}

// One batch's part of a round: r iterations of its chains, each one mutate, evaluate,
// accept and splat; its splats, pools' large steps and counters into o.
void MmltRender::runBatch(size_t ti, uint32_t r, uint32_t stripeShift, TaskOutput& o) {
    const auto start = Clock::now();
    MmltBatch& mb = batches_.local();
    mb.slices = plan_[ti];
    mb.target = map_;
    mb.splitForMap = !brightness_.empty();
    mb.stripeShift = stripeShift;
    mb.splatLengths = !lengthFilms_.empty();
    mb.clearSplats();
    for (SamplePool& p : mb.pools) p.clear();
    for (SamplePool& p : mb.mapPools) p.clear();
    mb.counters = MmltCounters();
    mb.delayed = opt_.delayedRejection && !whole_;  // (chosen once per render)
    mb.tallyLuminance = map_.exponent != 1.0f;      // (a tempered target: RenderStats::lengthMeanLuminance from the splats)
    for (uint64_t n = iteration_; n < iteration_ + r; ++n) {
        stages_.mutateChains(groups_, mb, opt_.seed, uint32_t(n), opt_.probLarge);
        stages_.evaluateProposals(scene_, mb, opt_.misBeta, rays_.local());
        stages_.acceptAndSplat(scene_, groups_, mb);
        if (mb.delayed) proposeAgain(scene_, groups_, mb, opt_.seed, uint32_t(n), opt_.misBeta, rays_.local());
    }
    for (uint32_t st = 0; st < kFilmStripes; ++st) {
        o.splats[st].swap(mb.splats[st]);
        o.splatLength[st].swap(mb.splatLength[st]);
        o.points[st].swap(mb.points[st]);
        o.pointLength[st].swap(mb.pointLength[st]);
    }
    o.pools.swap(mb.pools);
    mb.pools.resize(size_t(kMax_) + 1);
    o.mapPools.swap(mb.mapPools);
    mb.mapPools.resize(size_t(kMax_) + 1);
    o.counters = mb.counters;
    o.seconds = std::chrono::duration<double>(Clock::now() - start).count();
}

// The round's outputs into the film (in stripes of 2^stripeShift pixels, in parallel when
// parallelMerge) and the next pass's pools, every task's in batch order; across ranks every
// batch's large steps go to every rank first (roundPools: [batch * nk + k]).
void MmltRender::mergeRound(std::vector<TaskOutput>& outputs, std::vector<SamplePool>& roundPools, bool parallelMerge, uint32_t stripeShift) {
    const auto [b0, b1] = shareOf(ranks_, plan_.size());  // this rank's batches
    const size_t nk = size_t(kMax_) + 1;
    const bool maps = !brightness_.empty();
    std::vector<SamplePool> roundMapPools;
    if (ranks_) {  // every batch's large steps on every rank, in batch order
        roundPools.assign(plan_.size() * nk, SamplePool());
        for (size_t ti = b0; ti < b1; ++ti)
            for (size_t k = 0; k < nk; ++k) roundPools[ti * nk + k] = std::move(outputs[ti].pools[k]);
        exchangePools(roundPools, b0 * nk, (b1 - b0) * nk);
        if (maps) {
            roundMapPools.assign(plan_.size() * nk, SamplePool());
            for (size_t ti = b0; ti < b1; ++ti)
                for (size_t k = 0; k < nk; ++k) roundMapPools[ti * nk + k] = std::move(outputs[ti].mapPools[k]);
            exchangePools(roundMapPools, b0 * nk, (b1 - b0) * nk);
        }
    }
    // In batch order; a film point adds to its footprint's pixels in this stripe.
    auto mergeStripe = [&](uint32_t st) {
        for (const TaskOutput& o : outputs) {
            film_.addAll(o.splats[st].data(), o.splats[st].size());
            if (!lengthFilms_.empty())
                for (size_t i = 0; i < o.splats[st].size(); ++i) lengthFilms_[o.splatLength[st][i]].add(o.splats[st][i]);
            addPointSplatsInStripe(scene_, film_, lengthFilms_, o.points[st], o.pointLength[st], st, stripeShift);
        }
    };
    auto mergePool = [&](size_t k) {  // in batch order
        for (size_t ti = 0; ti < outputs.size(); ++ti) {
            if (maps) collectBrightness(ranks_ ? roundMapPools[ti * nk + k] : outputs[ti].mapPools[k], int(k));
            next_[k].add(ranks_ ? roundPools[ti * nk + k] : outputs[ti].pools[k]);
            thin(next_[k], int(k));
        }
    };
    if (parallelMerge) {
        tbb::parallel_for(uint32_t(0), kFilmStripes, mergeStripe);
        tbb::parallel_for(size_t(0), nk, mergePool);
    } else {
        mergeStripe(0);  // stripeShift 31: every splat is in stripe 0
        for (size_t k = 0; k < nk; ++k) mergePool(k);
    }
}

// The round's bookkeeping: counters and task times in batch order (deterministic), the
// passes' b sums, the iteration count and its measured cost, progress and the viewer.
void MmltRender::accountRound(const std::vector<TaskOutput>& outputs, uint32_t r, double roundStart) {
    const auto [b0, b1] = shareOf(ranks_, plan_.size());
    double longest = 0, sum = 0;
    for (const TaskOutput& o : outputs) {
        counters_.add(o.counters);
        longest = std::max(longest, o.seconds);
        sum += o.seconds;
    }
    ratioSum_ += sum > 0 ? longest / (sum / double(b1 - b0)) : 1.0;
    ++rounds_;
    for (const ChainGroup& g : groups_) {
        passB_[size_t(g.k)] += double(r) * double(g.weight) * g.count;
        stats_.proposals[size_t(g.k)] += uint64_t(r) * g.count;
    }
    weighted_ += double(r) * passWeight_;
    iteration_ += r;
    perIteration_ = (elapsed() - roundStart) / r;
    const double fraction = timed() ? std::min(1.0, elapsed() / opt_.timeBudget) : double(iteration_) / double(target_);
    if (opt_.progress) opt_.progress(fraction);
    paused_ += offerSnapshot(opt_, [&] {
        return Snapshot{image(), fraction, elapsed(), uint64_t(double(iteration_) * chains_ / pixels_), raysSoFar(rays_)};
    });
}

// Rounds of iterations until the pass ends at iteration passEnd (or the render does): each
// round runs every batch (runBatch), merges their outputs (mergeRound) and accounts for it.
void MmltRender::runRounds(uint64_t passEnd) {
    std::vector<TaskOutput> outputs(plan_.size());
    // The merge runs in parallel from 4 threads on; on fewer its synchronisation and the
    // splats' grouping cost more than they save (2 threads, Cornell box: CPU seconds 3.11
    // -> 3.36, medians of 5). Either way each pixel and each pool gets its additions in the
    // same order, so the image does not depend on the choice.
    const bool parallelMerge = std::min<size_t>(size_t(tbb::this_task_arena::max_concurrency()),
                                                tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism)) >= 4;
    uint32_t stripeShift = 31;  // stripes of 2^stripeShift pixels, at most kFilmStripes of them
    if (parallelMerge)
        for (stripeShift = 0; (uint64_t(pixels_) + (uint64_t(1) << stripeShift) - 1) >> stripeShift > kFilmStripes;) ++stripeShift;
    const uint32_t perRound = uint32_t(std::clamp(kProposalsPerRound / chains_, 1.0, 4096.0));
    const auto [b0, b1] = shareOf(ranks_, plan_.size());  // this rank's batches
    std::vector<SamplePool> roundPools;                   // split across ranks: [batch * nk + k], every batch's
    while (iteration_ < passEnd) {
        const uint32_t r = roundSize(perRound, passEnd);
        if (r == 0) {
            stopped_ = true;
            return;
        }
        const double roundStart = elapsed();
        tbb::parallel_for(b0, b1, [&](size_t ti) { runBatch(ti, r, stripeShift, outputs[ti]); });
        mergeRound(outputs, roundPools, parallelMerge, stripeShift);
        accountRound(outputs, r, roundStart);
    }
}

}  // namespace wmlt::mmlt_detail
