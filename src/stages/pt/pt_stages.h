// The path tracer's stages, in the order one bounce runs them:
//   generateCameraRays -> [ intersect -> resolveHits -> groupByMaterial -> sampleLights
//   -> traceShadows -> sampleBsdfs -> advancePaths ] per bounce
// (intersect and groupByMaterial are the wave's, wave.h). Each reads and writes the arrays
// of PtBatch named in its comment; none allocates.
#pragma once
#include <cstdint>

#include "scene/scene.h"
#include "stages/core/wave.h"
#include "stages/pt/pt_state.h"

namespace wmlt {

void generateCameraRays(const Scene& scene, PtBatch& b, const Tile& tile, int strataPerAxis, uint64_t seed);
void resolveHits(const Scene& scene, PtBatch& b, int depth, int minLength, int maxLength);
void sampleLights(const Scene& scene, PtBatch& b, int depth);
void traceShadows(const Scene& scene, PtBatch& b, int length, RayCounters& c);
void sampleBsdfs(const Scene& scene, PtBatch& b, int depth);
void advancePaths(const Scene& scene, PtBatch& b);
// Media (pt_media.cpp; a scene with SceneFeatures::media): after intersect, each path's
// free-path sample in its medium up to its hit, crossing pass-through boundaries (a
// scattering event then resolves as a Phase hit); the shadow rays with their transmittance
// through media and pass-through boundaries, instead of traceShadows.
// Emitting media: what they send back along the rays, added as contributions of length depth.
void traverseMedia(const Scene& scene, PtBatch& b, int depth, int minLength, int maxLength, RayCounters& c);
void traceShadowsThroughMedia(const Scene& scene, PtBatch& b, int length, RayCounters& c);

}  // namespace wmlt
