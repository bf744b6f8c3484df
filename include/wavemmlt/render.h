// The public entry point: render a scene with one of the tracers.
#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "wavemmlt/image.h"
#include "wavemmlt/scene_desc.h"

namespace wmlt {

constexpr int kMaxPathLength = 64;  // the scene format's limit

struct RenderOptions {
    TracerKind tracer = TracerKind::PT;
    int spp = 16;              // samples per pixel
    int strataPerAxis = 4;     // n: pixels are stratified n x n; n * n divides spp
    double timeBudget = 0;     // seconds; > 0: render rounds of spp samples until spent
    int threads = 0;           // 0: all hardware threads
    uint64_t seed = 0;
    int minPathLength = 1, maxPathLength = 10;
    float misBeta = 2;         // BPT and MMLT: power-heuristic exponent (1: the balance heuristic)
    // MMLT (spp: mutations per pixel).
    int chains = 65536;        // Markov chains in flight (any N >= 1)
    int bootstrap = 0;         // bootstrap samples per path length; 0: automatic
    float probLarge = 0.3f;    // probability of a large step, (0, 1]
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
};

struct RenderStats {
    std::string tracer;
    double seconds = 0;
    int threads = 0;
    uint64_t spp = 0;                 // samples per pixel completed (minimum over pixels)
    uint64_t raysIntersect = 0, raysOccluded = 0;
    uint64_t samplesNonfiniteDiscarded = 0;  // NaN or Inf contributions, left out of the image
    // Mean image luminance carried by paths of each length k (index k; 0 unused): the
    // per-length split of the image's mean, which MMLT's b_k must reproduce.
    std::vector<double> lengthMeanLuminance;
    bool cancelled = false;
    // MMLT, indexed by path length k (0 unused).
    struct Mmlt {
        std::vector<double> b;                    // b_k (mean target): bootstrap and large steps
        std::vector<double> bBootstrap;           // b_k from the bootstrap alone (allocation)
        std::vector<uint32_t> chainsAllocated;    // chains length k gets by b_k (largest remainders)
        std::vector<uint32_t> chains;             // chains run: at most the bootstrap's paths with c > 0
        std::vector<uint32_t> bootstrapNonzero;   // bootstrap samples with c > 0
        std::vector<uint64_t> proposalsPerChain;  // proposals each chain of length k made
        std::vector<uint64_t> proposedSmall, acceptedSmall, proposedLarge, acceptedLarge;
        uint64_t bootstrapSamples = 0;            // per length
        uint64_t mutations = 0;                   // proposals made in total
        uint64_t iterations = 0;                  // lockstep iterations (a chain makes steps_k per iteration)
        uint64_t replayMismatches = 0;            // seeded chains whose replay differed (a bug)
        uint64_t chainBytes = 0;                  // memory of the chain state
    } mmlt;
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

// The largest n with n * n dividing spp: the stratification grid for spp samples.
int strataForSpp(int spp);

}  // namespace wmlt
