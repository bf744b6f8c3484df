// What every tracer does at a pass or round boundary for a viewer (RenderView, render.h):
// make the image so far only when a viewer asked for a frame, publish it, and wait while
// the viewer has paused the render. Without a viewer it does nothing.
#pragma once
#include <tbb/enumerable_thread_specific.h>

#include <functional>

#include "stages/core/distributed.h"
#include "stages/core/wave.h"  // Tile, RayCounters
#include "wavemmlt/render.h"

namespace wmlt {

// Call while no batch runs. `snapshot` makes the image with the function that makes the
// final image. Returns the seconds the render was paused (0 without a viewer).
// Split across ranks, every rank calls it at the same boundary (distributed.h).
inline double offerSnapshot(const RenderOptions& opt, const std::function<Snapshot()>& snapshot) {
    if (opt.ranks && opt.ranks->many()) return offerSnapshotAcrossRanks(opt, snapshot);
    if (!opt.view) return 0;
    if (opt.view->wantsFrame()) opt.view->publish(snapshot());
    return opt.view->waitWhilePaused();
}

// Rays traced so far, summed over the threads' counters (while no batch runs).
inline uint64_t raysSoFar(const tbb::enumerable_thread_specific<RayCounters>& counters) {
    uint64_t n = 0;
    for (const RayCounters& c : counters) n += c.raysIntersect + c.raysOccluded;
    return n;
}

}  // namespace wmlt
