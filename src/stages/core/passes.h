// The schedule both tracers share: the image is cut into 16 x 16 tiles, and a pass runs
// one batch per tile (the tile's pixels times a range of sample indices) in parallel
// with TBB. Passes repeat until the samples per pixel are done or, with a time budget,
// in rounds of spp samples until the time is spent. Cancel and time are checked before
// each batch, so a render stops within one batch of either.
#pragma once
#include <tbb/enumerable_thread_specific.h>

#include <cstdint>
#include <functional>
#include <vector>

#include "stages/core/wave.h"  // Tile, RayCounters
#include "wavemmlt/image.h"
#include "wavemmlt/render.h"

namespace wmlt {

constexpr int kTileSize = 16;
constexpr uint32_t kMaxPathsPerBatch = 4096;

struct PassSchedule {
    std::vector<Tile> tiles;
    uint32_t samplesPerBatch = 1;  // samples per pixel in one batch (and one pass)
    size_t pathsPerBatch() const { return size_t(kTileSize) * kTileSize * samplesPerBatch; }
};

// maxPathsPerBatch bounds a batch's memory (at least one sample per pixel of a tile).
// A time budget (opt.timeBudget > 0) also caps a batch at 4 samples per pixel: the clock is
// read between batches, so a short batch ends the render close to its budget.
PassSchedule makePassSchedule(int width, int height, const RenderOptions& opt, uint32_t maxPathsPerBatch = kMaxPathsPerBatch);

struct PassResult {
    uint32_t completedSpp = 0;  // samples per pixel of the passes that completed
    double seconds = 0;
    bool stopped = false;    // cancelled or out of time
    bool cancelled = false;  // cancelled on some rank (split across ranks: docs/mpi.md)
    uint64_t passes = 0;     // passes completed
};

// What runPasses shows a viewer (opt.view) after each complete pass: the image of the
// passes so far, made by the function that makes the final image, and the ray counters.
struct PassImage {
    std::function<Image(uint32_t completedSpp)> image;
    const tbb::enumerable_thread_specific<RayCounters>* rays = nullptr;
};

// runBatch(tileIndex, tile) runs in parallel, each tile once per pass (split across ranks:
// this rank's tiles, tilesOfRank); endPass() runs on the calling thread after each pass that
// completed (an interrupted pass gets none: across ranks, a pass any rank interrupted), then
// the snapshot for a viewer (preview.h). Time paused by the viewer is not counted.
PassResult runPasses(const PassSchedule& schedule, const RenderOptions& opt, const std::function<void(size_t, const Tile&)>& runBatch,
                     const std::function<void()>& endPass, const PassImage& snapshot);

// The tiles a rank runs (opt.ranks; nullptr: all of them).
std::vector<size_t> tilesOfRank(const PassSchedule& schedule, const Distributed* ranks);

// The statistics every tracer reports the same way: name, time, spp, ray counts (summed
// over the threads' counters), cancellation and the scene's features.
RenderResult startResult(const char* tracer, const Scene& scene, const RenderOptions& opt, const PassResult& pr,
                         const tbb::enumerable_thread_specific<RayCounters>& counters);

}  // namespace wmlt
