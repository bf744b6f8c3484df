// The path tracer's wavefront stages, in the order one bounce runs them:
//   generateCameraRays -> [ intersectPaths -> resolveHits -> groupByMaterial
//   -> sampleLights -> traceShadows -> sampleBsdfs -> advancePaths ] per bounce.
// Each reads and writes the arrays of PtBatch named in its comment; none allocates.
#pragma once
#include <cstdint>

#include "scene/scene.h"
#include "stages/pt_state.h"

namespace wmlt {

struct PtTile {
    int x0, y0, x1, y1;                 // pixels [x0, x1) x [y0, y1)
    uint32_t sample0, sample1;          // sample indices [sample0, sample1)
};

struct PtCounters {
    uint64_t raysIntersect = 0, raysOccluded = 0;
};

// Writes slots (pixel, key, L) and paths (ray, beta, prev*): one camera ray per sample.
void generateCameraRays(const Scene& scene, PtBatch& b, const PtTile& tile, int strataPerAxis,
                        uint64_t seed);
// Traces the live paths' rays (closest hit).
void intersectPaths(const Scene& scene, PtBatch& b, bool coherent, PtCounters& c);
// Reads paths; adds emission (lights, environment) with MIS to slot L; writes hits for
// the paths that hit a surface.
void resolveHits(const Scene& scene, PtBatch& b, int depth, int minLength, int maxLength);
// Reads hits; writes order and kindStart (a counting sort by material kind).
void groupByMaterial(PtBatch& b);
// Next-event estimation: reads hits, writes shadow rays and their contributions.
void sampleLights(const Scene& scene, PtBatch& b, int depth);
// Traces the shadow rays; adds the unoccluded contributions (of path length `length`)
// to slot L.
void traceShadows(const Scene& scene, PtBatch& b, int length, PtCounters& c);
// Reads hits; samples each material's BSDF; writes next* and alive (Russian roulette).
void sampleBsdfs(const Scene& scene, PtBatch& b, int depth);
// Compacts the surviving hits into the next round's live paths, keeping their order.
void advancePaths(const Scene& scene, PtBatch& b);

}  // namespace wmlt
