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
// their weighted average: pass p's iterations count f_p = N_p / (N_p + 32 C) (its pools'
// sample count N_p, never their values): I = pixels * film / sum_p f_p iterations_p.
// One film serves every length. Splats are kept per batch and added in batch order after
// each round, pools likewise: a seed and any thread count give one image.
// Split across ranks (RenderOptions::ranks, docs/mpi.md): each rank runs a contiguous share
// of the pool tasks and of the batches; after each exchange every rank holds every task's
// pool samples in task order and merges them as one process does, so the pools, b_k, the
// allocation and the seeds are the same on every rank and the same as one process's; rank
// 0 makes every decision that depends on the clock; the films are summed on rank 0.
#include "stages/mmlt/mmlt_render.h"

#include <tbb/global_control.h>

#include "scene/scene_lights.h"
#include "stages/core/splat_passes.h"

namespace wmlt {

namespace mmlt_detail {

namespace {
// "4.19 M", "812 k", "96": a count for messages.
std::string countText(double n) {
    char buf[32];
    if (n >= 1e9) std::snprintf(buf, sizeof buf, "%.3g G", n * 1e-9);
    else if (n >= 1e6) std::snprintf(buf, sizeof buf, "%.3g M", n * 1e-6);
    else if (n >= 1e4) std::snprintf(buf, sizeof buf, "%.3g k", n * 1e-3);
    else std::snprintf(buf, sizeof buf, "%.0f", n);
    return buf;
}
std::string secondsText(double s) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f s", s);
    return buf;
}
}  // namespace

MmltRender::MmltRender(const Scene& scene, const RenderOptions& opt, bool whole)
    : scene_(scene), opt_(opt), ranks_(opt.ranks && opt.ranks->many() ? opt.ranks : nullptr), t0_(Clock::now()), kMin_(std::max(1, opt.minPathLength)), kMax_(opt.maxPathLength),
      whole_(whole), lo_(whole ? 0 : kMin_), hi_(whole ? 0 : kMax_),
      batches_([&scene, whole, minLength = kMin_, maxLength = opt.maxPathLength] {
          MmltBatch mb;
          mb.reserve(kBatchChains + size_t(maxLength) + 1, maxLength, batchNeeds(scene), whole);
          mb.bpt.minLength = minLength;
          mb.bpt.maxLength = maxLength;
          setNumbersRead(scene, mb);
          return mb;
      }),
      film_(scene.camera.width, scene.camera.height) {
    pixels_ = double(scene.camera.width) * double(scene.camera.height);
    targetMutations_ = double(opt.spp) * pixels_;
    // --chains auto: with --spp chosen here from the mutations alone; under --time after the
    // bootstrap (chooseTimedChains), until then at its largest (the memory check below).
    double chosen = double(opt.chains);
    if (autoChains_) {
        chosen = timed() ? double(kAutoChainsMost) : double(autoChains(targetMutations_));
        if (!timed())
            chainsReason_ = "auto: " + std::to_string(uint32_t(chosen)) + " for " + countText(targetMutations_) +
                            " mutations, " + std::to_string(int(kAutoIterationsPerChain)) +
                            " iterations per chain, within " + std::to_string(kAutoChainsLeast) + " to " +
                            std::to_string(kAutoChainsMost);
    } else {
        chainsReason_ = "--chains " + std::to_string(opt.chains);
    }
    // No more chains than mutations asked for (a small image at few mutations per pixel).
    const double asked = timed() ? chosen : std::min(chosen, targetMutations_);
    if (!timed() && asked < chosen) chainsReason_ += ", no more than the " + countText(targetMutations_) + " mutations";
    chains_ = uint32_t(std::max(1.0, asked));
    target_ = uint64_t(std::ceil(targetMutations_ / double(chains_)));
    const size_t n = size_t(kMax_) + 1;
    pools_.resize(n);
    next_.resize(n);
    passB_.assign(n, 0.0);
    thinRounds_.assign(n, 0);
    stats_.b.assign(n, 0.0);
    stats_.chains.assign(n, 0);
    for (auto* v : {&stats_.chainsSeeded, &stats_.distinctSeeds, &stats_.bootstrapSamples, &stats_.bootstrapNonzero,
                    &stats_.poolSamples, &stats_.proposals, &stats_.proposedSmall, &stats_.acceptedSmall,
                    &stats_.proposedLarge, &stats_.acceptedLarge})
        v->assign(n, 0);
    if (opt.lengthImages)
        for (size_t k = 0; k < n; ++k) lengthFilms_.emplace_back(scene.camera.width, scene.camera.height);
    // Memory, refused before anything large is allocated: the chain state at its largest
    // (every chain at MaxPathLength), the films, a round's splats.
    const double chainBytes = double(chains_) * double(chainBytesOf(kMax_));
    const double filmBytes = 24.0 * pixels_ * double(1 + lengthFilms_.size());
    const double mem = physicalMemoryBytes();
    if (mem > 0 && chainBytes + filmBytes > 0.75 * mem)
        throw InputError(std::string(whole_ ? "PSSMLT" : "MMLT") + " would need " + bytesText(chainBytes) + " of chain state and " + bytesText(filmBytes) +
                         " of films, more than 3/4 of this machine's " + bytesText(mem));
}

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
    std::vector<SamplePool> pools;
    MmltCounters counters;
    double seconds = 0;
};

// Rounds of iterations until the pass ends at iteration passEnd (or the render does).
void MmltRender::runRounds(uint64_t passEnd) {
    std::vector<TaskOutput> outputs(plan_.size());
    // The merge runs in parallel from 4 threads on; on fewer its synchronisation and the
    // splats' grouping cost more than they save (2 threads, Cornell box: CPU seconds 3.11
    // -> 3.36, medians of 5). Either way each pixel and each pool gets its additions in the
    // same order, so the image does not depend on the choice.
    const bool parallelMerge =
        std::min<size_t>(size_t(tbb::this_task_arena::max_concurrency()),
                         tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism)) >= 4;
    uint32_t stripeShift = 31;  // stripes of 2^stripeShift pixels, at most kFilmStripes of them
    if (parallelMerge)
        for (stripeShift = 0; (uint64_t(pixels_) + (uint64_t(1) << stripeShift) - 1) >> stripeShift > kFilmStripes;)
            ++stripeShift;
    const uint32_t perRound = uint32_t(std::clamp(kProposalsPerRound / chains_, 1.0, 4096.0));
    const auto [b0, b1] = shareOf(ranks_, plan_.size());  // this rank's batches
    const size_t nk = size_t(kMax_) + 1;
    std::vector<SamplePool> roundPools;  // split across ranks: [batch * nk + k], every batch's
    while (iteration_ < passEnd) {
        // The round's iterations r (rank 0 decides; 0: the time is spent).
        uint32_t r = uint32_t(std::min<uint64_t>(perRound, passEnd - iteration_));
        if (timed()) {
            // A time budget: the last rounds shrink so as to end on time, each taking about
            // half the time left, so that a machine that slows down during one (another
            // process starts) overshoots by a part of that round, not by all of the time left.
            const double left = opt_.timeBudget - elapsed();
            r = left <= 0.5 * perIteration_ && iteration_ > 0 ? 0
                : perIteration_ > 0 ? uint32_t(std::clamp(std::floor(0.5 * left / perIteration_ + 0.5), 1.0, double(r)))
                                    : 1;
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
            mb.stripeShift = stripeShift;
            mb.splatLengths = !lengthFilms_.empty();
            mb.clearSplats();
            for (SamplePool& p : mb.pools) p.clear();
            mb.counters = MmltCounters();
            for (uint64_t n = iteration_; n < iteration_ + r; ++n) {
                mutateChains(groups_, mb, opt_.seed, uint32_t(n), opt_.probLarge);
                evaluateProposals(scene_, mb, opt_.misBeta, rays_.local());
                acceptAndSplat(scene_, groups_, mb);
            }
            TaskOutput& o = outputs[ti];
            for (uint32_t st = 0; st < kFilmStripes; ++st) {
                o.splats[st].swap(mb.splats[st]);
                o.splatLength[st].swap(mb.splatLength[st]);
                o.points[st].swap(mb.points[st]);
                o.pointLength[st].swap(mb.pointLength[st]);
            }
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
        for (size_t ti = 0; ti < outputs.size(); ++ti) {  // in batch order: deterministic
            TaskOutput& o = outputs[ti];
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
}

// --chains auto under --time: from the mutations the rest of the budget allows at the
// bootstrap's measured rate (a mutation costs about a pool sample), and never fewer than
// kAutoChainsLeastTimed or two batches per worker of the job (every rank's threads, as many
// on each rank as on rank 0), rank 0's figures on every rank.
void MmltRender::chooseTimedChains() {
    const double left = std::max(0.0, opt_.timeBudget - elapsed());
    const double mutations = left / std::max(sampleSeconds_, 1e-12);
    const double workers = double(tbb::this_task_arena::max_concurrency()) * (ranks_ ? ranks_->size() : 1);
    const uint32_t least =
        uint32_t(std::clamp(2.0 * kBatchChains * workers, double(kAutoChainsLeastTimed), double(kAutoChainsMost)));
    chains_ = uint32_t(agreeAtBoundary(autoChains(mutations, kAutoIterationsPerChain, least)).value);
    chainsReason_ = "auto: " + std::to_string(chains_) + " for the " + countText(mutations) +
                    " mutations the bootstrap's rate predicts in the " + secondsText(left) + " left, " +
                    std::to_string(int(kAutoIterationsPerChain)) + " iterations per chain, within " +
                    std::to_string(least) + " (at least " + std::to_string(kAutoChainsLeastTimed) +
                    " and 2 batches of 256 per worker, " + std::to_string(int(workers)) + " workers) to " +
                    std::to_string(kAutoChainsMost);
}

RenderResult MmltRender::run() {
    const int nLengths = hi_ - lo_ + 1;
    bootstrap();
    if (timed() && autoChains_) chooseTimedChains();  // before the pools are thinned to the chains' needs
    stats_.bBootstrap.assign(size_t(kMax_) + 1, 0.0);
    for (int k = lo_; k <= hi_; ++k) {
        stats_.bootstrapNonzero[size_t(k)] = pools_[size_t(k)].lit.size();
        stats_.bBootstrap[size_t(k)] = pools_[size_t(k)].mean();
        thin(pools_[size_t(k)], k);
    }
    // Under a time budget one iteration of all chains (about C samples) may cost at most 2%
    // of the budget, or the render could not end within it (--time 3 with 65536 chains on
    // a slow build): the chains are capped there, and --stats and a warning say so.
    stats_.chainsAsked = autoChains_ ? 0 : chains_;
    stats_.chainsAuto = autoChains_;
    stats_.chainsRun = chains_;  // before the cap
    if (timed()) {  // rank 0's figure on every rank
        const double cap = std::floor(0.02 * opt_.timeBudget / std::max(sampleSeconds_, 1e-12));
        chains_ = uint32_t(agreeAtBoundary(uint64_t(std::clamp(cap, 1.0, double(chains_)))).value);
    }
    if (chains_ < stats_.chainsRun)
        chainsReason_ += "; capped to " + std::to_string(chains_) + ": one iteration of them all costs at most 2% of --time";
    stats_.chainsRun = chains_;
    stats_.chainsReason = chainsReason_;
    if (opt_.notice) opt_.notice(std::string(whole_ ? "PSSMLT: " : "MMLT: ") + std::to_string(chains_) + " chains (" + chainsReason_ + ")");
    if (!allocateChains())
        throw InputError("no light reaches the camera: the bootstrap's " +
                         std::to_string(*std::min_element(stats_.bootstrapSamples.begin() + lo_,
                                                          stats_.bootstrapSamples.begin() + hi_ + 1)) +
                         (whole_ ? " or more whole BPT samples (path lengths " : " or more samples of each path length ") +
                         std::to_string(kMin_) + ".." + std::to_string(kMax_) + (whole_ ? ")" : "") +
                         " all carry zero radiance (check the lights, MinPathLength and MaxPathLength)");
    // Iterations per pass: 2 to 8 passes in a render, 32 to 1024 iterations each (each
    // pass replays its C seeds: 1 / passLength of the render at most). Restarts renew the
    // chains when the pools hold more lit seeds than there are chains, and only copy the
    // same few seeds again when they hold fewer (docs/mmlt-chains.md, "Fewer, longer
    // passes"): 8 passes when every chain of the first allocation can start from a seed of
    // its own, down to 2 as the share rho of chains that can falls.
    if (timed()) {  // rank 0's figure on every rank
        const double left = std::max(0.0, opt_.timeBudget - elapsed());
        target_ = agreeAtBoundary(uint64_t(left / std::max(sampleSeconds_, 1e-12) / double(chains_))).value;
    }
    double distinct = 0;
    for (const ChainGroup& g : groups_) distinct += double(std::min<size_t>(g.count, pools_[size_t(g.k)].lit.size()));
    const double rho = distinct / double(chains_), passes = 2.0 + 6.0 * std::min(1.0, rho);
    passLength_ = opt_.passLength > 0 ? uint32_t(opt_.passLength)
                                      : uint32_t(std::clamp(double(target_) / passes, 32.0, 1024.0));
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
            tracePool(0, std::vector<uint32_t>(size_t(kMax_) + 1, fresh), false);
            for (int k = lo_; k <= hi_; ++k) {
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

}  // namespace mmlt_detail

uint32_t autoChains(double mutations, double iterationsPerChain, uint32_t least, uint32_t most) {
    const double batches = std::floor(std::max(0.0, mutations) / std::max(iterationsPerChain, 1.0) / 256.0);
    return uint32_t(std::clamp(256.0 * batches, double(std::min(least, most)), double(most)));
}

uint64_t mmltChainBytes(int k, bool media) { return uint64_t(StrategyLayout::size(k, media)) * 8 + 5 * 4 + 12 + 8; }

RenderResult renderMmlt(const Scene& scene, const RenderOptions& opt) { return mmlt_detail::MmltRender(scene, opt).run(); }

}  // namespace wmlt
