// Structure-of-arrays state of one batch of path-tracing samples (a tile of pixels times
// a range of sample indices): a PathWave (wave.h: the live paths and their hits) and
//   slots   - one per sample, for the life of the batch: pixel, random key, radiance L;
//   paths   - per live path: throughput and MIS data (compacted with the wave);
//   hits    - per hit: the surface (WMLT_HIT_SURFACE_ARRAYS) and the next bounce;
//   shadow  - the shadow rays of next-event estimation.
// Every round of the wavefront reads one group and writes the next (docs/architecture.md).
#pragma once
#include <embree3/rtcore.h>

#include <cstdint>
#include <vector>

#include "kernels/bsdf.h"
#include "stages/core/film.h"
#include "stages/core/wave.h"

namespace wmlt {

// prevPdf: solid-angle pdf of the BSDF sample that made the path's ray; prevDelta: it was
// a delta lobe (no MIS on what it hits); anyNonSpecular: some bounce of the path so far was
// not a delta lobe (pbrt-v4's anyNonSpecularBounces: its later hits take the regularized
// table, PtBatch::regularizedOffset). nextBeta, nextPdf, nextDelta: the same for the
// next bounce, written by BSDF sampling at the hit's index. hitKey: the hit's sample key
// (read by the flat loops in hit order). hitNs, hitKd, hitBeta: per hit
// (a scene with matte surfaces), its shading normal, Kd and its path's throughput, for the
// matte flat loops (matteScatter; matteNeeValues), scatterOk what matteScatter decided.
// shadowL: the shadow ray's unoccluded contribution to shadowSlot. neeLight, neePmf: per
// hit, the light it chose and that choice's probability (a scene of several lights:
// chooseLights);
// neeP, neeDist, neePdf, neeOk: its sample of that light when it is a rectangle
// (sampleLights' flat loops; neeWi in localX/Y/Z); the matte loops (matteNeeValuesOf, with
// the light's radiance neeLe, and shadowRaysTo) write the shadow ray (neeOrigin, neeDir,
// neeTfar), its contribution neeL and whether its f is not black.
#define WMLT_PT_ARRAYS(X)                                                                    \
    X(uint32_t, pixel) X(uint64_t, key) X(Vec3, L)                                         \
    X(Vec3, beta) X(float, prevPdf) X(uint8_t, prevDelta) X(uint8_t, anyNonSpecular)       \
    WMLT_HIT_SURFACE_ARRAYS(X) X(uint64_t, hitKey) X(Vec3, nextBeta) X(float, nextPdf)     \
    X(uint8_t, nextDelta) X(RTCRay, shadow) X(uint32_t, shadowSlot) X(Vec3, shadowL)
// Allocated only for a scene with matte surfaces.
#define WMLT_PT_MATTE_ARRAYS(X) X(Vec3, hitNs) X(Vec3, hitKd) X(Vec3, hitBeta) X(uint32_t, scatterOk)
// Allocated only for a scene of several lights.
#define WMLT_PT_LIGHT_CHOICE_ARRAYS(X) X(uint32_t, neeLight) X(float, neePmf)
// Allocated only for a scene with a rectangle light (Scene::anyRectLight).
#define WMLT_PT_RECT_LIGHT_ARRAYS(X)                                                         \
    X(Vec3, neeLe) X(Vec3, neeP) X(float, neeDist) X(float, neePdf) X(uint8_t, neeOk)                     \
    X(Vec3, neeOrigin) X(Vec3, neeDir) X(float, neeTfar) X(Vec3, neeL) X(uint32_t, neeSend)

// Allocated only for a scene with media (SceneFeatures::media; docs/media.md): per path its
// medium (-1: vacuum), whether its ray scattered in it this round and where (mediumT), and
// its last scattering vertex (vertexP: the reference of its emitter hits' MIS after
// crossing boundaries); per hit the media on either side (for a medium vertex or a surface
// that is no boundary, both the path's); per shadow ray the medium it starts in.
#define WMLT_PT_MEDIA_ARRAYS(X)                                                              \
    X(int32_t, medium) X(uint8_t, mediumEvent) X(float, mediumT) X(Vec3, vertexP)          \
    X(int32_t, hitMediumIn) X(int32_t, hitMediumOut) X(int32_t, shadowMedium)

struct PtBatch : PathWave {
    WMLT_PT_ARRAYS(WMLT_SOA_ARRAY)
    size_t numShadow = 0;
    ContributionTally tally;  // per batch
    // pbrt's regularize, chosen once per render (renderPathTracing): Scene::regularizedOffset,
    // the table a path's hits take once anyNonSpecular; 0: the render does not regularize.
    uint32_t regularizedOffset = 0;

    WMLT_PT_LIGHT_CHOICE_ARRAYS(WMLT_SOA_ARRAY)
    WMLT_PT_RECT_LIGHT_ARRAYS(WMLT_SOA_ARRAY)
    WMLT_PT_MATTE_ARRAYS(WMLT_SOA_ARRAY)
    WMLT_PT_MEDIA_ARRAYS(WMLT_SOA_ARRAY)

    // The optional arrays as the scene needs them (batchNeeds).
    void reserve(size_t n, const BatchNeeds& needs) {
        resizeWave(n, needs);
        WMLT_PT_ARRAYS(WMLT_SOA_RESIZE)
        if (needs.severalLights) { WMLT_PT_LIGHT_CHOICE_ARRAYS(WMLT_SOA_RESIZE) }
        if (needs.rectLights) { WMLT_PT_RECT_LIGHT_ARRAYS(WMLT_SOA_RESIZE) }
        if (needs.matte) { WMLT_PT_MATTE_ARRAYS(WMLT_SOA_RESIZE) }
        if (needs.media) { WMLT_PT_MEDIA_ARRAYS(WMLT_SOA_RESIZE) }
    }
};

// A contribution of path length `length` to slot's radiance (film.h, ContributionTally).
inline void addRadiance(PtBatch& b, uint32_t slot, Vec3 c, int length) {
    if (b.tally.take(c, length)) b.L[slot] += c;
}

// Primary sample layout of a path-tracing sample (see rng.h): dimensions 0-1 jitter the
// pixel position within its stratum, 2-3 pick the lens point, and bounce d >= 1 reads
// dimensions kBounceBase + (d - 1) * kBounceStride + (0: light choice, 1-2: light point,
// 3: BSDF lobe, 4-5: BSDF direction, 6: Russian roulette).
constexpr uint32_t kBounceBase = 4;
constexpr uint32_t kBounceStride = 7;
inline uint32_t bounceDim(int depth, uint32_t j) { return kBounceBase + uint32_t(depth - 1) * kBounceStride + j; }


}  // namespace wmlt
