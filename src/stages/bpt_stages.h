// Bidirectional path tracing's wavefront stages, in the order a batch runs them:
//   generateBptCameraPaths -> [ intersectBptPaths -> resolveBptHits -> groupBptHits
//     -> sampleBptBsdfs -> advanceBptPaths ] per camera segment,
//   generateBptLightPaths  -> the same rounds for the light subpaths,
//   connectBpt (s = 0 added directly; s = 1, t = 1 and s, t >= 2 as batched shadow rays,
//     flushed by traceBptConnections).
// The MIS weights come from kernels/mis.h (bptMisWeight) on the per-vertex densities.
#pragma once
#include <cstdint>

#include "scene/scene.h"
#include "stages/bpt_state.h"
#include "stages/pt_stages.h"  // PtTile, PtCounters

namespace wmlt {

// The key of BPT sample s of pixel: a stream apart from the PT's and LT's.
uint64_t bptSampleKey(uint64_t seed, uint32_t pixel, uint32_t sample);

// Solid-angle density with which the camera generates direction w from a lens point
// (uniform on the image plane: 1 / (A cos^3 theta)); 0 outside the image.
float cameraPdfDir(const Camera& c, Vec3 lens, Vec3 w);

// Writes slots (pixel, key, L = 0), camera vertex z_0 and one path per slot.
void generateBptCameraPaths(const Scene& scene, BptBatch& b, const PtTile& tile, int strataPerAxis,
                            uint64_t seed);
// Writes light vertex y_0 (Env for the environment: a point on the disc of LT's
// emission, lt_stages.h) and one path per slot with a usable emission sample.
void generateBptLightPaths(const Scene& scene, BptBatch& b);
// Traces the live paths (closest hit).
void intersectBptPaths(const Scene& scene, BptBatch& b, bool coherent, PtCounters& c);
// Reads paths; appends the vertex each hits to v (camera walk: an emitter ends the path
// with a Light vertex, an escape with an Env vertex when the scene has an environment;
// light walk: emitters absorb); writes hits for the paths that go on (the vertex is
// below v's capacity - 1).
void resolveBptHits(const Scene& scene, BptBatch& b, BptVertices& v, bool cameraWalk);
// Counting sort of the hits by material kind.
void groupBptHits(BptBatch& b);
// Samples each hit's BSDF (mode: Radiance for the camera walk, Importance for the light
// walk); writes the previous vertex's pdfRev, the hit vertex's delta, next* and alive.
// d: the vertex's index in its subpath (random-number layout, roulette from d = 3).
void sampleBptBsdfs(const Scene& scene, BptBatch& b, BptVertices& v, bool cameraWalk);
// Compacts the surviving hits into the next round's paths.
void advanceBptPaths(const Scene& scene, BptBatch& b, const BptVertices& v);
// Every strategy (s, t) with s + t - 1 in [minLength, maxLength]: s = 0 to L, the
// others to conns (flushed through traceBptConnections when full and at the end).
void connectBpt(const Scene& scene, BptBatch& b, int minLength, int maxLength, float misBeta, PtCounters& c);
// Traces the conns; adds the unoccluded ones to L (camera side) or splats (t = 1).
void traceBptConnections(const Scene& scene, BptBatch& b, PtCounters& c);

}  // namespace wmlt
