// The public entry point: render a scene with one of the tracers.
#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "wavemmlt/image.h"
#include "wavemmlt/scene_desc.h"

namespace wmlt {

constexpr int kMaxPathLength = 64;  // the scene format's limit

// The image of the work a render has completed so far, made by the same function that
// makes its final image, and what the render has done (RenderView).
struct Snapshot {
    Image image;
    double fraction = 0;  // done, in [0, 1] (with a time budget: the budget spent)
    double seconds = 0;   // render time so far; paused time is left out
    uint64_t spp = 0;     // samples per pixel so far (MMLT: mutations per pixel)
    uint64_t rays = 0;    // rays traced so far (closest hit and shadow)
};

// A viewer of a running render (--view, --display-server): RenderOptions::view. Tracers
// call it on their own thread at each pass (PT, LT, BPT) or round (MMLT) boundary, while
// no batch runs: stages/core/preview.h, offerSnapshot().
class RenderView {
public:
    virtual ~RenderView() = default;
    // True when a viewer has asked for a frame since the last publish (one atomic load):
    // the image is made only then.
    virtual bool wantsFrame() const = 0;
    virtual void publish(Snapshot snapshot) = 0;
    // Blocks while the viewer has paused the render; returns when it resumes or the render
    // is cancelled, with the seconds it waited (left out of the time budget and the stats).
    virtual double waitWhilePaused() = 0;
};

class Distributed;  // the ranks of a render split across processes (stages/core/distributed.h)

// MMLT's target function (docs/mmlt-levers.md): the path's luminance (Hachisuka et al. 2014),
// or from the second pass on its luminance over a smoothed estimate of its pixel's brightness
// (Hoberock and Hart 2010), so that the chains spend their mutations where the relative
// error is.
enum class MmltTarget { Luminance, Relative };
// Its names (--mmlt-target, --stats' mmlt_target); parseMmltTarget: false for another name.
inline const char* mmltTargetName(MmltTarget t) { return t == MmltTarget::Relative ? "relative" : "luminance"; }
inline bool parseMmltTarget(const std::string& name, MmltTarget& t) {
    for (MmltTarget x : {MmltTarget::Luminance, MmltTarget::Relative})
        if (name == mmltTargetName(x)) {
            t = x;
            return true;
        }
    return false;
}

// MMLT's film steps (docs/mmlt-levers.md): small steps that move only the raster point and
// keep every other number. Off; learned (the default): from the second pass on, 0.3 of the
// small steps of each length whose small steps were accepted less than 0.6 of the time in the
// last pass; always: 0.3 of every length's small steps from the first pass on.
enum class FilmSteps { Off, Learned, Always };
// Its names (--mmlt-film-steps, --stats' mmlt_film_steps); parseFilmSteps: false for another name.
inline const char* filmStepsName(FilmSteps f) { return f == FilmSteps::Learned ? "learned" : f == FilmSteps::Always ? "always" : "off"; }
inline bool parseFilmSteps(const std::string& name, FilmSteps& f) {
    for (FilmSteps x : {FilmSteps::Off, FilmSteps::Learned, FilmSteps::Always})
        if (name == filmStepsName(x)) {
            f = x;
            return true;
        }
    return false;
}

struct RenderOptions {
    TracerKind tracer = TracerKind::PT;
    int spp = 16;           // samples per pixel
    int strataPerAxis = 4;  // n: pixels are stratified n x n; n * n divides spp
    double timeBudget = 0;  // seconds; > 0: render rounds of spp samples until spent
    int threads = 0;        // 0: all hardware threads
    uint64_t seed = 0;
    int minPathLength = 1, maxPathLength = 10;
    // BPT, MMLT, PSSMLT: the MIS power heuristic's exponent (1: the balance heuristic); 0:
    // the tracer's own (misBetaOf): 1 for MMLT, whose target is then the same F / sum_j p_j
    // for every strategy of a path (on the estimator suite a few per cent better than 2,
    // within the seeds' spread: docs/mmlt-levers.md), 2 for BPT and PSSMLT (Veach's choice
    // for a sample that sums every strategy).
    float misBeta = 0;
    // MMLT (spp: mutations per pixel).
    int chains = 0;          // Markov chains in flight (any N >= 1); 0: auto (autoChains, stages/mmlt/mmlt.h)
    int bootstrap = 0;       // samples per path length in the first pass's pool; 0: automatic
    float probLarge = 0.3f;  // probability of a large step, (0, 1]
    int passLength = 0;      // iterations of every chain between restarts from a new pool; 0: automatic
    // MMLT's levers (issue 44; docs/mmlt-levers.md), each chosen per pass and fixed within it.
    MmltTarget mmltTarget = MmltTarget::Luminance;
    // The target's exponent beta in (0, 1]: c = luminance^beta (a tempered target,
    // kernels/mmlt_target.h; 1: the luminance). MMLT only (PSSMLT keeps the luminance). Not
    // the default: on the estimator suite 0.5 wins on the seed room and loses on the
    // volumetric caustic and Veach Ajar (docs/mmlt-levers.md).
    float mmltTargetExponent = 1.0f;
    bool learnSteps = false;  // each length's small-step size from its chains' acceptance in the last pass
    // A rejected large step gets a second proposal in the same iteration, a small step, with
    // the acceptance that keeps the chain exact (delayed rejection; mmlt_delayed.cpp).
    bool delayedRejection = false;
    // Film steps (FilmSteps): small steps that move only the raster point, by 3 sigma
    // (mmlt_stages.cpp, proposeFilmStep; which lengths: mmlt_learn.cpp, learnFilmSteps).
    // Learned by default: on the estimator suite it loses nowhere beyond the seeds' spread
    // and wins on Veach Ajar (docs/mmlt-levers.md). MMLT only (PSSMLT has none).
    FilmSteps filmSteps = FilmSteps::Learned;
    // --spectral: render with sampled wavelengths (docs/spectral.md), every tracer; scenes
    // with principled or blend materials or media given by RGB grids render in RGB and
    // RenderStats::spectralReason says why.
    bool spectral = false;
    // spectral is the scene format's default (Settings::spectral: pbrt-v4 files, Mitsuba files
    // that give spectra), not asked for: a scene that cannot render so renders RGB with its
    // reason, but no warning.
    bool spectralByDefault = false;
    // BPT: write one EXR per strategy (s, t), weighted and unweighted, into this folder.
    std::string strategyImages;
    // BPT and MMLT: also return the image of each path length k (RenderResult::lengthImages;
    // they add up to the image). Costs a film per length; for tests and diagnostics.
    bool lengthImages = false;
    // Set from another thread (e.g. a SIGINT handler) to stop early; the image so far
    // is returned, each pixel averaged over the samples it received.
    const std::atomic<bool>* cancel = nullptr;
    // Called now and then with the fraction done in [0, 1] (never with a time budget's
    // unknown total: then with the fraction of the budget spent).
    std::function<void(double)> progress;
    // Called with a one-line notice of a choice the render made (MMLT: the chain count and
    // why), once, before the work it governs; nullptr: none.
    std::function<void(const std::string&)> notice;
    // A viewer: offered the image so far between passes or rounds (nullptr: none, no cost).
    RenderView* view = nullptr;
    // A render split across processes (mpirun; docs/mpi.md): every rank calls render() with
    // the same options and its own Distributed; the ranks share out the work, and rank 0's
    // result holds the job's image and statistics. nullptr: this process renders alone.
    Distributed* ranks = nullptr;
    // Tests only: MMLT's first replay of a seed is made to differ from its pool entry, so that
    // the report of a replay mismatch (renderWarnings; an InvariantError where WMLT_DCHECKs
    // are on, src/kernels/check.h) can be tested. Never set by the application.
    bool plantReplayMismatch = false;
};

// The MIS exponent a render with these options uses (RenderOptions::misBeta), and which
// values RenderOptions::misBeta may take (renderScene and the interactive panel check it).
inline float misBetaOf(const RenderOptions& o) { return o.misBeta > 0 ? o.misBeta : o.tracer == TracerKind::MMLT ? 1.0f : 2.0f; }
inline bool misBetaValid(float beta) { return beta == 0 || (beta >= 0.5f && beta <= 16); }
constexpr const char* kMisBetaRange = "the MIS exponent must be in [0.5, 16] (0: the tracer's own)";

struct RenderStats {
    std::string tracer;
    double seconds = 0;
    int threads = 0;
    uint64_t spp = 0;  // samples per pixel completed (minimum over pixels)
    uint64_t raysIntersect = 0, raysOccluded = 0;
    uint64_t samplesNonfiniteDiscarded = 0;  // NaN or Inf contributions, left out of the image
    // Mean image luminance carried by paths of each length k (index k; 0 unused): the
    // per-length split of the image's mean, which MMLT's b_k must reproduce.
    std::vector<double> lengthMeanLuminance;
    bool cancelled = false;
    float misBeta = 0;  // BPT, MMLT, PSSMLT: the MIS exponent used (misBetaOf; 0: other tracers)
    // Whether the render was spectral (RenderOptions::spectral) and, when asked for (or the
    // format's default: spectralByDefault) and not done, why not.
    bool spectral = false;
    std::string spectralReason;
    bool spectralByDefault = false;
    bool dispersionAsIndex = false;  // an RGB render of a dispersive dielectric: its index at 550 nm
    // The ranks of a render split across processes (RenderOptions::ranks), per rank: the
    // payload bytes it received (their sum is the job's traffic), and seconds inside
    // exchanges (waiting for the others included).
    struct Ranks {
        int count = 1;
        std::vector<uint64_t> bytes;
        std::vector<double> seconds;
        uint64_t exchanges = 0;   // exchanges each rank made
        uint64_t boundaries = 0;  // pass (PT, LT, BPT) or round (MMLT) boundaries they met at
    } ranks;
    // MMLT, indexed by path length k (0 unused). A pass: the chains start from a pool of
    // independent samples, run passLength iterations, and are restarted from the next pool.
    struct Mmlt {
        std::vector<double> b;                   // b_k = E[c]: the pools' means, weighted by their passes' iterations
        std::vector<double> bBootstrap;          // b_k of the first pass's pool (the bootstrap)
        std::vector<uint32_t> chains;            // chains of length k in the last pass
        std::vector<uint64_t> chainsSeeded;      // chains of length k started, all passes together
        std::vector<uint64_t> distinctSeeds;     // distinct pool samples they started from, all passes
        std::vector<uint64_t> bootstrapNonzero;  // bootstrap samples with c > 0
        std::vector<uint64_t> poolSamples;       // pool samples of length k, all passes (fresh and large steps)
        std::vector<uint64_t> proposals;         // proposals made by chains of length k
        std::vector<uint64_t> proposedSmall, acceptedSmall, proposedLarge, acceptedLarge;
        std::vector<uint64_t> proposedDelayed, acceptedDelayed;  // second proposals (RenderOptions::delayedRejection)
        std::vector<uint64_t> proposedFilm, acceptedFilm;        // film steps (RenderOptions::filmSteps)
        // Accepted and proposed steps summed over the lengths: [0] small, [1] large, [2] film
        // steps (the three kinds of an iteration's proposal: they add up to `proposals`).
        void stepTotals(uint64_t accepted[3], uint64_t proposed[3]) const {
            for (int i = 0; i < 3; ++i) accepted[i] = proposed[i] = 0;
            for (size_t k = 0; k < proposedSmall.size(); ++k) {
                accepted[0] += acceptedSmall[k];
                proposed[0] += proposedSmall[k];
                accepted[1] += acceptedLarge[k];
                proposed[1] += proposedLarge[k];
                accepted[2] += acceptedFilm[k];
                proposed[2] += proposedFilm[k];
            }
        }
        std::vector<uint64_t> bootstrapSamples;    // bootstrap samples of length k (the first pass's pool)
        uint64_t mutations = 0;                    // proposals made in total
        uint64_t iterations = 0;                   // proposals each chain made, all passes (the image's divisor)
        uint32_t passes = 0, passLength = 0;       // passes started; iterations per pass
        uint32_t tasksPerRound = 0;                // batches of chains run in parallel
        double longestTaskRatio = 0;               // longest task / mean task of a round, averaged over rounds
        uint64_t replayed = 0;                     // seeded chains replayed (all in the first pass, then 1 in 8)
        uint64_t replayMismatches = 0;             // replays that differed from their pool entry (a bug)
        uint64_t chainBytes = 0;                   // memory of the chain state (largest pass)
        uint32_t chainsAsked = 0, chainsRun = 0;   // --chains (0: auto), and the chains run (fewer only under a tight --time)
        bool chainsAuto = false;                   // --chains auto chose chainsRun
        std::string chainsReason;                  // how the count was chosen
        std::vector<std::vector<double>> bByRank;  // b as each rank computed it (split across ranks)
        // The levers (RenderOptions::mmltTarget, learnSteps; docs/mmlt-levers.md). The
        // relative target: the maps made (one per pass after the first), their tiles' side
        // in pixels, and the last map's least and greatest scale (mean brightness over the
        // tile's); b is then in the target's units, not luminance.
        MmltTarget target = MmltTarget::Luminance;
        float targetExponent = 1;  // beta (RenderOptions::mmltTargetExponent)
        uint32_t targetMaps = 0, targetTileSize = 0;
        double targetScaleLeast = 0, targetScaleMost = 0;
        bool learnedSteps = false;
        bool delayedRejection = false;
        FilmSteps filmSteps = FilmSteps::Off;
        std::vector<float> filmStepShare;        // each length's share of film steps in the last pass
        std::vector<float> smallStepSigma;       // each length's small steps' size in the last pass
        std::vector<uint64_t> poolDigestByRank;  // a hash of each rank's pools, every pass (split across ranks)
    } mmlt;
    // Bytes of the render's large buffers (films, chain state, pools, splat lists), by name.
    std::vector<std::pair<std::string, uint64_t>> buffers;
    double mraysPerSecond() const { return seconds > 0 ? (raysIntersect + raysOccluded) / seconds * 1e-6 : 0; }
};

// One BPT strategy's image (RenderOptions::strategyImages): its share of the image
// (MIS-weighted) and its own estimate of the length-(s + t - 1) image (unweighted).
struct StrategyImage {
    int s = 0, t = 0;
    Image weighted, unweighted;
};

struct RenderResult {
    Image image;
    RenderStats stats;
    std::string featuresJson;
    std::vector<StrategyImage> strategyImages;  // BPT with strategyImages set
    std::vector<Image> lengthImages;            // index k (0 unused): with RenderOptions::lengthImages
};

// Throws InputError for settings it cannot render (and "not implemented yet" for the
// tracers a later version adds).
RenderResult render(SceneDesc scene, const RenderOptions& options);

// What a finished render should tell its user (one line each, without "warning: "): samples
// that were NaN or infinite, MMLT chains fewer than asked, replayed MMLT seeds that differed
// from their pool entries (an estimator bug: the image may be biased).
std::vector<std::string> renderWarnings(const RenderResult& r);

// The largest n with n * n dividing spp: the stratification grid for spp samples.
int strataForSpp(int spp);

}  // namespace wmlt
