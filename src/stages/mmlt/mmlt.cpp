// The MMLT driver (mmlt.md; docs/mmlt-chains.md for the many-chain design and the
// measurements that chose it). The render is a sequence of passes (MmltRender::run reads as
// its phases); each pass:
//  1. tracePool: the pool of every length k is a set of independent uniform samples of u:
//     the bootstrap in the first pass, then fresh samples and the previous pass's
//     large-step proposals (each an independent uniform sample, its key kept);
//     b_k,p = the pool's mean c;
//  2. allocateChains: the C chains go to the lengths whose pool has light in proportion to
//     b_k (the mean of all pools so far), by largest remainders, never at random, at least
//     one each;
//  3. seedChains: each chain starts at a pool sample chosen in proportion to c (systematic
//     resampling) and replays it: the replay must give the same c bit for bit;
//  4. runRounds (mmlt_rounds.cpp): passLength iterations of every chain (mutate, evaluate, accept and splat),
//     in rounds of batches run in parallel; each splat carries the weight
//     b_k,p / chains_k,p of its length and pass.
// A chain started from a pool by resampling in proportion to c and weighted by the pool's
// mean c gives an unbiased estimate after any number of steps (importance resampling: the
// pair (pool, start) has the target as its weighted marginal, and the Metropolis kernel
// keeps it), so every pass is unbiased whatever its length and its chains' count, and so is
// their weighted average: pass p's iterations count f_p = N_p / (N_p + 32 C) (its pools'
// sample count N_p, never their values): I = pixels * film / sum_p f_p iterations_p.
// Between passes the render may learn what the next pass holds fixed (RenderOptions'
// levers, off by default: mmlt_learn.cpp, docs/mmlt-levers.md): a relative target, made from
// samples no pool holds, and each length's small-step size; each pass stays exact.
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
    : scene_(scene),
      opt_(opt),
      ranks_(opt.ranks && opt.ranks->many() ? opt.ranks : nullptr),
      t0_(Clock::now()),
      kMin_(std::max(1, opt.minPathLength)),
      kMax_(opt.maxPathLength),
      whole_(whole),
      stages_(whole ? kPssmltStages : kMmltStages),
      lo_(whole ? 0 : kMin_),
      hi_(whole ? 0 : kMax_),
      batches_([this, &scene, whole, minLength = kMin_, maxLength = opt.maxPathLength] {
          MmltBatch mb;
          BatchNeeds needs = batchNeeds(scene);
          needs.spectral = spectral_;
          mb.reserve(kBatchChains + size_t(maxLength) + 1, maxLength, needs, whole);
          mb.bpt.spectra = spectralMode_.spectra();
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
            chainsReason_ = "auto: " + std::to_string(uint32_t(chosen)) + " for " + countText(targetMutations_) + " mutations, " +
                            std::to_string(int(kAutoIterationsPerChain)) + " iterations per chain, within " + std::to_string(kAutoChainsLeast) +
                            " to " + std::to_string(kAutoChainsMost);
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
    for (auto* v : {&stats_.chainsSeeded, &stats_.distinctSeeds, &stats_.bootstrapSamples, &stats_.bootstrapNonzero, &stats_.poolSamples,
                    &stats_.proposals, &stats_.proposedSmall, &stats_.acceptedSmall, &stats_.proposedLarge, &stats_.acceptedLarge,
                    &stats_.proposedDelayed, &stats_.acceptedDelayed, &stats_.proposedFilm, &stats_.acceptedFilm})
        v->assign(n, 0);
    if (opt.lengthImages)
        for (size_t k = 0; k < n; ++k) lengthFilms_.emplace_back(scene.camera.width, scene.camera.height);
    planTargetMap();
    sigma_.assign(n, kSmallStepSigma);
    // Film steps: always, or (learned) from the second pass on (learnFilmSteps).
    filmStep_.assign(n, opt.filmSteps == FilmSteps::Always && !whole_ ? kFilmStepShare : 0.0f);
    // Memory, refused before anything large is allocated: the chain state at its largest
    // (every chain at MaxPathLength), the films, a round's splats.
    const double chainBytes = double(chains_) * double(chainBytesOf(kMax_));
    const double filmBytes = 24.0 * pixels_ * double(1 + lengthFilms_.size());
    const double mem = physicalMemoryBytes();
    if (mem > 0 && chainBytes + filmBytes > 0.75 * mem)
        throw InputError(std::string(whole_ ? "PSSMLT" : "MMLT") + " would need " + bytesText(chainBytes) + " of chain state and " +
                         bytesText(filmBytes) + " of films, more than 3/4 of this machine's " + bytesText(mem));
}

// --chains auto under --time: from the mutations the rest of the budget allows at the
// bootstrap's measured rate (a mutation costs about a pool sample), and never fewer than
// kAutoChainsLeastTimed or two batches per worker of the job (every rank's threads, as many
// on each rank as on rank 0), rank 0's figures on every rank.
void MmltRender::chooseTimedChains() {
    const double left = std::max(0.0, opt_.timeBudget - elapsed());
    const double mutations = left / std::max(sampleSeconds_, 1e-12);
    const double workers = double(tbb::this_task_arena::max_concurrency()) * (ranks_ ? ranks_->size() : 1);
    const uint32_t least = uint32_t(std::clamp(2.0 * kBatchChains * workers, double(kAutoChainsLeastTimed), double(kAutoChainsMost)));
    chains_ = uint32_t(agreeAtBoundary(autoChains(mutations, kAutoIterationsPerChain, least)).value);
    chainsReason_ = "auto: " + std::to_string(chains_) + " for the " + countText(mutations) + " mutations the bootstrap's rate predicts in the " +
                    secondsText(left) + " left, " + std::to_string(int(kAutoIterationsPerChain)) + " iterations per chain, within " +
                    std::to_string(least) + " (at least " + std::to_string(kAutoChainsLeastTimed) + " and 2 batches of 256 per worker, " +
                    std::to_string(int(workers)) + " workers) to " + std::to_string(kAutoChainsMost);
}

// The bootstrap's figures (--stats), then its pools thinned to the chains' needs.
void MmltRender::keepBootstrap() {
    stats_.bBootstrap.assign(size_t(kMax_) + 1, 0.0);
    for (int k = lo_; k <= hi_; ++k) {
        stats_.bootstrapNonzero[size_t(k)] = pools_[size_t(k)].lit.size();
        stats_.bBootstrap[size_t(k)] = pools_[size_t(k)].mean();
        thin(pools_[size_t(k)], k);
    }
}

// Under a time budget one iteration of all chains (about C samples) may cost at most 2%
// of the budget, or the render could not end within it (--time 3 with 65536 chains on
// a slow build): the chains are capped there, and --stats, the notice and a warning say so.
void MmltRender::capChainsToBudget() {
    stats_.chainsAsked = autoChains_ ? 0 : chains_;
    stats_.chainsAuto = autoChains_;
    stats_.chainsRun = chains_;  // before the cap
    if (timed()) {               // rank 0's figure on every rank
        const double cap = std::floor(0.02 * opt_.timeBudget / std::max(sampleSeconds_, 1e-12));
        chains_ = uint32_t(agreeAtBoundary(uint64_t(std::clamp(cap, 1.0, double(chains_)))).value);
    }
    if (chains_ < stats_.chainsRun)
        chainsReason_ += "; capped to " + std::to_string(chains_) + ": one iteration of them all costs at most 2% of --time";
    stats_.chainsRun = chains_;
    stats_.chainsReason = chainsReason_;
    if (opt_.notice) opt_.notice(std::string(whole_ ? "PSSMLT: " : "MMLT: ") + std::to_string(chains_) + " chains (" + chainsReason_ + ")");
}

InputError MmltRender::noLight() const {
    return InputError("no light reaches the camera: the bootstrap's " +
                      std::to_string(*std::min_element(stats_.bootstrapSamples.begin() + lo_, stats_.bootstrapSamples.begin() + hi_ + 1)) +
                      (whole_ ? " or more whole BPT samples (path lengths " : " or more samples of each path length ") + std::to_string(kMin_) +
                      ".." + std::to_string(kMax_) + (whole_ ? ")" : "") +
                      " all carry zero radiance (check the lights, MinPathLength and MaxPathLength)");
}

// Iterations per chain (target_: a time budget's from the bootstrap's rate) and per pass: 2
// to 8 passes in a render, 32 to 1024 iterations each (each pass replays its C seeds:
// 1 / passLength of the render at most). Restarts renew the chains when the pools hold more
// lit seeds than there are chains, and only copy the same few seeds again when they hold
// fewer (docs/mmlt-chains.md, "Fewer, longer passes"): 8 passes when every chain of the
// first allocation can start from a seed of its own, down to 2 as the share rho of chains
// that can falls (counted in the lit seeds the probe predicts, not in the pools: the
// passes' lengths weigh the passes, so they must not follow the values of the pools they
// weigh; with no probe held out, --bootstrap N or a budget spent in the probe, 8 passes).
// Fresh samples per length and pass (the large steps feed the pools too; the fresh ones
// keep probing every length, with chains or not): C / 8 in all, at least 64 per length.
void MmltRender::planPasses() {
    if (timed()) {  // rank 0's figure on every rank
        const double left = std::max(0.0, opt_.timeBudget - elapsed());
        target_ = agreeAtBoundary(uint64_t(left / std::max(sampleSeconds_, 1e-12) / double(chains_))).value;
    }
    double distinct = 0;
    for (const ChainGroup& g : groups_) distinct += probeLit_.empty() ? double(g.count) : std::min(double(g.count), probeLit_[size_t(g.k)]);
    const double rho = distinct / double(chains_);
    passes_ = 2.0 + 6.0 * std::min(1.0, rho);
    passLength_ = opt_.passLength > 0 ? uint32_t(opt_.passLength) : uint32_t(std::clamp(double(target_) / passes_, 32.0, 1024.0));
    fresh_ = std::max<uint32_t>(64, chains_ / (8 * uint32_t(hi_ - lo_ + 1)));
}

// Under --time, after the first pass (roundSeconds: its rounds'), the passes planned again
// for the iterations the rest of the budget allows at the chains' own measured cost: the
// bootstrap's cost per sample, which planned the first, is not the chains' (its samples are
// spread over the lengths unlike the chains: half of them equally). The Cornell box at
// --time 6 planned passes of 595 iterations from it and ran 23 of them.
void MmltRender::replanPasses(double roundSeconds) {
    if (!timed() || opt_.passLength > 0 || iteration_ == 0) return;
    const double left = std::max(0.0, opt_.timeBudget - elapsed()), perIteration = roundSeconds / double(iteration_);
    const double iterations = double(iteration_) + left / std::max(perIteration, 1e-12);
    passLength_ = uint32_t(agreeAtBoundary(uint64_t(std::clamp(iterations / passes_, 32.0, 1024.0))).value);
}

// Rank 0 decides after a pass: a new pass, the end, or, with too little time left for a
// restart (restartSeconds: the last one's) to pay, the chains go on to the end (a pass may
// be any length: it stays unbiased).
MmltRender::NextPass MmltRender::decideNextPass(double restartSeconds) {
    uint64_t next = uint64_t(NextPass::New);
    if (!timed() && iteration_ >= target_) next = uint64_t(NextPass::End);
    if (timed()) {
        const double left = opt_.timeBudget - elapsed();
        next = uint64_t(left <= 0.5 * perIteration_ ? NextPass::End : left < 2 * restartSeconds + perIteration_ ? NextPass::GoOn : NextPass::New);
    }
    const Agreement a = agreeAtBoundary(next);
    return a.cancel ? NextPass::End : NextPass(a.value);
}

// The next pass's pools: this pass's large steps and fresh samples, one more batch of each
// pool (SamplePool, poolWeights), thinned; the chains allocated to them (false: no light in
// any pool).
bool MmltRender::refillPools() {
    retarget();        // RenderOptions::mmltTarget = Relative: a new target, the pools under it
    learnFromSteps();  // RenderOptions::learnSteps, filmSteps: each length's small steps
    std::vector<uint64_t> large(size_t(kMax_) + 1, 0);
    uint64_t allLarge = 0;
    for (int k = lo_; k <= hi_; ++k) allLarge += large[size_t(k)] = next_[size_t(k)].count;
    tracePool(0, std::vector<uint32_t>(size_t(kMax_) + 1, fresh_), false, next_);
    for (int k = lo_; k <= hi_; ++k) {
        const double share = allLarge ? double(large[size_t(k)]) / double(allLarge) : 1.0 / double(hi_ - lo_ + 1);
        pools_[size_t(k)].addBatch(next_[size_t(k)], next_[size_t(k)].count - large[size_t(k)], share);
        next_[size_t(k)].clear();
    }
    batchLarge_.push_back(allLarge);
    weighPools();
    for (int k = lo_; k <= hi_; ++k) thin(pools_[size_t(k)], k);
    return allocateChains();
}

// A pass whose pools have no light: its estimate is 0, its iterations count.
void MmltRender::skipDarkPass() {
    iteration_ += passLength_;
    weighted_ += double(passLength_) * passWeight_;
    ++pass_;
}

// The render: the bootstrap and the chain count, then passes, each seeding the chains from
// the pools and running rounds, until the iterations (or the time) are spent.
RenderResult MmltRender::run() {
    bootstrap();
    if (timed() && autoChains_) chooseTimedChains();  // before the pools are thinned to the chains' needs
    keepBootstrap();
    capChainsToBudget();
    if (!allocateChains()) throw noLight();
    planPasses();
    double restartSeconds = 0;  // the last pass's start: pool, allocation, seeding and replay
    while (true) {
        const double passStart = elapsed();
        if (pass_ > 0) {
            const NextPass next = decideNextPass(restartSeconds);
            if (next == NextPass::End) break;
            if (next == NextPass::GoOn) {
                runRounds(std::numeric_limits<uint64_t>::max());
                break;
            }
            if (!refillPools()) {
                skipDarkPass();
                continue;
            }
        }
        size_t entries = 0;
        for (const SamplePool& p : pools_) entries += p.lit.size();
        poolEntries_ = std::max(poolEntries_, entries);
        seedChains();
        restartSeconds = elapsed() - passStart;
        ++stats_.passes;
        runRounds(timed() ? iteration_ + passLength_ : std::min<uint64_t>(target_, iteration_ + passLength_));
        if (pass_ == 0 && !stopped_) replanPasses(elapsed() - passStart - restartSeconds);
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

uint64_t mmltChainBytes(int k, bool media, bool spectral) { return uint64_t(StrategyLayout::size(k, media, spectral)) * 8 + 5 * 4 + 12 + 8; }

RenderResult renderMmlt(const Scene& scene, const RenderOptions& opt) { return mmlt_detail::MmltRender(scene, opt).run(); }

}  // namespace wmlt
