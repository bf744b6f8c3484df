// The light tracer's wavefront stages (t = 1 strategies), in the order a batch runs them:
//   [ generateEnvCameraRays -> traceConnections ]          (length 1, environment)
//   generateLightPaths -> traceConnections                  (length 1, area lights)
//   [ intersect -> resolveLightHits -> groupByMaterial -> connectToCamera
//     -> traceConnections -> sampleLightBsdfs -> advanceLightPaths ] per segment
// (intersect and groupByMaterial are the wave's, wave.h). Each reads and writes the arrays
// of LtBatch named in its comment; splats are appended to LtBatch::splats in a fixed order.
#pragma once
#include <cstdint>

#include "scene/scene.h"
#include "stages/core/wave.h"
#include "stages/lt/lt_state.h"

namespace wmlt {

// The key of light-tracing sample s of pixel: a stream apart from the path tracer's.
uint64_t ltSampleKey(uint64_t seed, uint32_t pixel, uint32_t sample);

// Writes conns: one camera ray per sample (stratified like the PT's) whose value is the
// environment's radiance; unoccluded, it is the length-1 contribution.
void generateEnvCameraRays(const Scene& scene, LtBatch& b, const Tile& tile, int strataPerAxis, uint64_t seed);
// Writes slots (key), paths (ray, beta) and, when connectLength1, conns from each area
// light's point to the camera (length 1).
void generateLightPaths(const Scene& scene, LtBatch& b, const Tile& tile, uint64_t seed, bool connectLength1);
// Traces the conns (rtcOccluded1M); appends the unoccluded ones (all of path length
// `length`) to splats.
void traceConnections(const Scene& scene, LtBatch& b, int length, RayCounters& c);
// Traces the live paths (closest hit).
// Reads paths; writes hits for paths that hit a surface with a material (emitters
// without one absorb).
void resolveLightHits(const Scene& scene, LtBatch& b);
// Reads hits; writes order and kindStart (counting sort by material kind).
// Reads hits of non-delta materials; writes conns to a lens point (vertex after d
// segments: path length d + 1).
void connectToCamera(const Scene& scene, LtBatch& b, int d);
// Reads hits; samples each BSDF in TransportMode::Importance; writes next* and alive.
void sampleLightBsdfs(const Scene& scene, LtBatch& b, int d);
// Compacts the surviving hits into the next round's paths, keeping their order.
void advanceLightPaths(const Scene& scene, LtBatch& b);

}  // namespace wmlt
