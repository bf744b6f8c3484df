// MmltRender: the MMLT driver's state and its phases (docs/architecture.md, "The
// Metropolis wavefront"; the algorithm in mmlt.cpp's opening comment). Defined in five
// files: mmlt.cpp (construction and the render's phases: bootstrap figures, chain count,
// passes), mmlt_rounds.cpp (a pass's rounds), mmlt_pool.cpp (tracing the pools and
// exchanging them between ranks), mmlt_chains.cpp (allocating chains to lengths, seeding and
// replaying them, planning the batches) and mmlt_resolve.cpp (the image and the stats).
// Internal to src/stages.
#pragma once
#include "stages/mmlt/mmlt.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <numeric>
#include <unordered_set>

#include "stages/core/distributed_films.h"
#include "stages/core/film.h"
#include "stages/core/memory.h"
#include "stages/core/passes.h"
#include "stages/core/preview.h"
#include "stages/mmlt/mmlt_stages.h"
#include "stages/pssmlt/pssmlt_stages.h"
#include "wavemmlt/error.h"

namespace wmlt::mmlt_detail {

constexpr uint32_t kBatchChains = 256;          // chains per batch: the tasks of a round
constexpr double kProposalsPerRound = 1 << 18;  // bounds the splat lists (~8 MB) and a round's time
constexpr double kTargetTiles = 256;            // the relative target's map: at most this many tiles
constexpr double kTargetFloor = 0.1;            // its brightness floor, a share of the image's mean
constexpr double kTargetAcceptance = 0.4;       // learned step sizes: the small steps' acceptance sought
constexpr double kStepGain = 3;                 // and the gain of log sigma on the gap
constexpr double kFilmStepBelow = 0.6;          // film steps: for lengths whose small steps' acceptance is below this
constexpr float kFilmStepShare = 0.3f;          // this share of their small steps

using Clock = std::chrono::steady_clock;

struct TaskOutput;  // a batch's part of a round (mmlt.cpp)

// One pool-tracing task: samples [i0, i0 + n) of length k.
struct PoolTask {
    int k;
    uint32_t i0, n;
};

// MMLT's driver, and PSSMLT's (whole = true: one group of chains, k = 0, whose proposals
// are whole BPT samples: pssmlt_stages.h; its pool is pools_[0]).
class MmltRender {
public:
    MmltRender(const Scene& scene, const RenderOptions& opt, bool whole = false);
    RenderResult run();

private:
    bool tracePool(uint32_t from, const std::vector<uint32_t>& to, bool bootstrap, std::vector<SamplePool>& into,
                   std::vector<SamplePool>* odd = nullptr);
    void bootstrap();
    double chainCostRatio(const std::vector<PoolTask>& tasks, const std::vector<double>& taskSeconds, size_t t0, size_t t1) const;
    std::vector<double> shares(const std::vector<SamplePool>& p) const;
    void closeBootstrap(std::vector<SamplePool>& even, std::vector<SamplePool>& odd);
    void weighPools();
    void replanPasses(double roundSeconds);
    void chooseTimedChains();
    bool allocateChains();
    void seedChains();
    void planBatches();
    void replaySeeds();
    // The phases of a render (run): the bootstrap's figures, the chain count's cap, the
    // passes' plan, and after each pass the decision and the next pools.
    void keepBootstrap();
    void capChainsToBudget();
    InputError noLight() const;
    void planPasses();
    enum class NextPass : uint64_t { New, End, GoOn };
    NextPass decideNextPass(double restartSeconds);
    bool refillPools();
    void skipDarkPass();
    // A pass's rounds (runRounds), each sized (roundSize), run batch by batch (runBatch:
    // mutate, evaluate, accept and splat), merged (mergeRound) and accounted (accountRound).
    void runRounds(uint64_t passEnd);
    uint32_t roundSize(uint32_t perRound, uint64_t passEnd);
    void runBatch(size_t ti, uint32_t r, uint32_t stripeShift, TaskOutput& o);
    void mergeRound(std::vector<TaskOutput>& outputs, std::vector<SamplePool>& roundPools, bool parallelMerge, uint32_t stripeShift);
    void accountRound(const std::vector<TaskOutput>& outputs, uint32_t r, double roundStart);
    RenderResult resolve();
    // What the render learns between passes (mmlt_learn.cpp): the relative target's map (its
    // tiles, the brightness sums of the samples set aside for it, a new map at a pass
    // boundary), each length's small-step size and its share of film steps.
    void planTargetMap();
    void collectBrightness(const SamplePool& p, int k);
    void retarget();
    void learnFromSteps();
    std::vector<uint64_t> passSmallSteps();
    void learnStepSizes(const std::vector<uint64_t>& counts);
    void learnFilmSteps(const std::vector<uint64_t>& counts);
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
    // the length (its last allocation; before the first, its share of the chains as the
    // bootstrap was spread), at least 2^13.
    size_t poolCapacity(int k) const {
        size_t n = 0;
        if (stats_.passes) {
            n = stats_.chains[size_t(k)];
        } else if (const uint64_t all = std::accumulate(stats_.bootstrapSamples.begin(), stats_.bootstrapSamples.end(), uint64_t(0))) {
            n = size_t(double(chains_) * double(stats_.bootstrapSamples[size_t(k)]) / double(all));
        }
        return std::max<size_t>(size_t(1) << 13, 8 * n);
    }
    void thin(SamplePool& pool, int k) {
        // Each length counts its own thinnings (its comb offsets are hashed from the seed,
        // the length and that count), so that the lengths' pools can be merged in parallel.
        if (pool.lit.size() > poolCapacity(k)) thinPool(pool, poolCapacity(k) / 2, mix64(opt_.seed + uint64_t(k)), thinRounds_[size_t(k)]++);
    }

    const Scene& scene_;
    const RenderOptions& opt_;
    Distributed* ranks_;       // nullptr: one process
    bool cancelled_ = false;   // agreed by the ranks at a boundary
    uint64_t poolDigest_ = 0;  // a hash of the pools of every pass
    Clock::time_point t0_;
    int kMin_, kMax_;            // the path lengths rendered
    bool whole_;                 // PSSMLT
    const ChainStages& stages_;  // MMLT's or PSSMLT's (whole_), chosen once
    // --spectral: the scene's spectra, or RGB with the reason, chosen once; a spectral render's
    // rows have one more number, the wavelengths'.
    SpectralMode spectralMode_ = chooseSpectralMode(scene_, opt_.spectral);
    bool spectral_ = spectralMode_.spectral;
    int lo_, hi_;  // the groups' k (the pools'): MMLT kMin..kMax, PSSMLT 0
    // Bytes of state per chain of group k.
    uint64_t chainBytesOf(int k) const {
        return whole_ ? pssmltChainBytes(kMax_, scene_.features.media, spectral_) : mmltChainBytes(k, scene_.features.media, spectral_);
    }
    double pixels_, targetMutations_;
    uint32_t chains_ = 1;                 // C
    bool autoChains_ = opt_.chains == 0;  // --chains auto
    std::string chainsReason_;            // how C was chosen (--stats, the notice)
    uint64_t target_ = 0;                 // iterations per chain (spp renders)
    uint32_t passLength_ = 1;
    double passes_ = 8;    // the passes planned (planPasses)
    uint32_t fresh_ = 64;  // fresh pool samples per length and pass (planPasses)
    uint32_t pass_ = 0;
    uint64_t iteration_ = 0;  // iterations of every chain so far
    double passWeight_ = 1;   // f_p of this pass (allocateChains)
    double weighted_ = 0;     // sum over rounds of f_p times iterations: the image's divisor
    bool stopped_ = false;
    double paused_ = 0;         // seconds a viewer held the render between rounds
    double perIteration_ = 0;   // seconds per iteration of all chains, measured
    double sampleSeconds_ = 0;  // seconds per pool sample, measured

    tbb::enumerable_thread_specific<MmltBatch> batches_;
    tbb::enumerable_thread_specific<RayCounters> rays_;
    std::vector<SamplePool> pools_, next_;       // [k]: this pass's pool, the next one's batch (large steps, then fresh)
    std::vector<uint64_t> batchLarge_;           // [batch]: the large steps of every length in the pools' batch
    std::vector<double> chainShare_;             // [k]: the chains' share the probe predicts (empty: before it)
    std::vector<double> probeLit_;               // [k]: lit samples the probe predicts in the bootstrap (empty: no probe held out)
    std::vector<double> passB_;                  // sum over rounds of iterations times b_k
    std::vector<uint32_t> thinRounds_;           // [k]: thinnings of length k's pools so far
    std::vector<ChainGroup> groups_;             // this pass's chains, one group per length with chains
    std::vector<std::vector<BatchSlice>> plan_;  // per batch: its slices
    SplatFilm film_;
    std::vector<SplatFilm> lengthFilms_;  // RenderOptions::lengthImages only
    RenderStats::Mmlt stats_;
    MmltCounters counters_;
    double ratioSum_ = 0;
    uint64_t rounds_ = 0;
    size_t poolEntries_ = 0;  // the most pool entries held at once
    // The relative target (mmlt_learn.cpp): the map the tasks read (no scale: luminance),
    // its tiles' side in pixels, their scales, and per length k the luminance sums of its
    // samples per tile ([k * tiles + tile]) and their count.
    TargetMap map_ = [this] {  // (the tempered target's exponent: MMLT's, chosen once)
        TargetMap m;
        m.exponent = whole_ ? 1.0f : opt_.mmltTargetExponent;
        return m;
    }();
    std::vector<float> sigma_;     // [k]: the small steps' size of length k's chains this pass
    std::vector<float> filmStep_;  // [k]: the share of their small steps that are film steps
    MmltCounters passCounters_;    // counters_ when the pass started (learnFromSteps)
    int tileSize_ = 1;
    std::vector<float> scale_;
    std::vector<double> brightness_;
    std::vector<uint64_t> brightnessSamples_;
};

}  // namespace wmlt::mmlt_detail
