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
#include "scene/scene_spectra.h"
#include "stages/core/film.h"
#include "stages/core/wave.h"

namespace wmlt {

// Per slot (one per sample, for the life of the batch):
//   pixel: the sample's pixel
//   key: its random key (rng.h; dimensions: bounceDim below)
//   L: the radiance it has gathered
// Per live path (compacted with the wave):
//   beta: the path's throughput
//   prevPdf: solid-angle pdf of the BSDF sample that made the path's ray
//   prevDelta: that sample was a delta lobe (no MIS on what it hits)
//   anyNonSpecular: some bounce so far was not a delta lobe (pbrt-v4's
//     anyNonSpecularBounces: its later hits take the regularized table, regularizedOffset)
// Per hit:
//   WMLT_HIT_SURFACE_ARRAYS: the surface (wave.h)
//   hitKey: the hit's sample key (read by the flat loops in hit order)
//   nextBeta: the throughput for the next bounce (BSDF sampling, at the hit's index)
//   nextPdf: the next bounce's prevPdf (likewise)
//   nextDelta: the next bounce's prevDelta (likewise)
// Per shadow ray (next-event estimation):
//   shadow: the ray
//   shadowSlot: the slot it adds to
//   shadowL: its unoccluded contribution
// clang-format off
#define WMLT_PT_ARRAYS(X)                                                                    \
    X(uint32_t, pixel) X(uint64_t, key) X(Vec3, L)                                         \
    X(Vec3, beta) X(float, prevPdf) X(uint8_t, prevDelta) X(uint8_t, anyNonSpecular)       \
    WMLT_HIT_SURFACE_ARRAYS(X) X(uint64_t, hitKey) X(Vec3, nextBeta) X(float, nextPdf)     \
    X(uint8_t, nextDelta) X(RTCRay, shadow) X(uint32_t, shadowSlot) X(Vec3, shadowL)
// clang-format on
// Allocated only for a scene with matte surfaces; per hit, for the matte flat loops
// (matteScatter; matteNeeValues):
//   hitNs: its shading normal
//   hitKd: its Kd
//   hitBeta: its path's throughput
//   scatterOk: what matteScatter decided (the bounce is valid)
#define WMLT_PT_MATTE_ARRAYS(X) X(Vec3, hitNs) X(Vec3, hitKd) X(Vec3, hitBeta) X(uint32_t, scatterOk)
// Allocated only for a scene of several lights; per hit (chooseLights):
//   neeLight: the light it chose
//   neePmf: that choice's probability
#define WMLT_PT_LIGHT_CHOICE_ARRAYS(X) X(uint32_t, neeLight) X(float, neePmf)
// Allocated only for a scene with a rectangle light (Scene::anyRectLight); per hit, its
// sample of its chosen light when that is a rectangle (sampleLights' flat loops; the
// direction neeWi in localX/Y/Z), then what the matte loops (matteNeeValuesOf,
// shadowRaysTo) make of it:
//   neeLe: the light's radiance
//   neeP: the point sampled on the light
//   neeDist: the distance to it
//   neePdf: the sample's solid-angle density
//   neeOk: the sample is valid
//   neeOrigin: the shadow ray's origin
//   neeDir: its direction
//   neeTfar: its length
//   neeL: its contribution
//   neeSend: f is not black (the ray is traced)
// clang-format off
#define WMLT_PT_RECT_LIGHT_ARRAYS(X)                                                         \
    X(Vec3, neeLe) X(Vec3, neeP) X(float, neeDist) X(float, neePdf) X(uint8_t, neeOk)                     \
    X(Vec3, neeOrigin) X(Vec3, neeDir) X(float, neeTfar) X(Vec3, neeL) X(uint32_t, neeSend)
// clang-format on

// Allocated only for a scene with media (SceneFeatures::media; docs/media.md):
//   medium: per path, its medium (-1: vacuum)
//   mediumEvent: its ray scattered in it this round
//   mediumT: where
//   vertexP: its last scattering vertex (its emitter hits' MIS reference across boundaries)
//   hitMediumIn, hitMediumOut: per hit, the media on either side (a medium vertex or a
//     surface that is no boundary: both the path's)
//   shadowMedium: per shadow ray, the medium it starts in
// clang-format off
#define WMLT_PT_MEDIA_ARRAYS(X)                                                              \
    X(int32_t, medium) X(uint8_t, mediumEvent) X(float, mediumT) X(Vec3, vertexP)          \
    X(int32_t, hitMediumIn) X(int32_t, hitMediumOut) X(int32_t, shadowMedium)
// clang-format on

// Allocated only for a spectral render (RenderOptions::spectral; docs/spectral.md):
//   lambda: per slot, its wavelengths (the colour channels' meaning)
//   hitMaterial: per hit, its material (SceneDesc::materials; -1: a medium vertex)
#define WMLT_PT_SPECTRAL_ARRAYS(X) X(Wavelengths, lambda) X(int32_t, hitMaterial)

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
    WMLT_PT_SPECTRAL_ARRAYS(WMLT_SOA_ARRAY)
    const SpectralScene* spectra = nullptr;  // a spectral render's (chosen once per render); nullptr: RGB

    // The optional arrays as the scene needs them (batchNeeds).
    void reserve(size_t n, const BatchNeeds& needs) {
        resizeWave(n, needs);
        WMLT_PT_ARRAYS(WMLT_SOA_RESIZE)
        if (needs.severalLights) {
            WMLT_PT_LIGHT_CHOICE_ARRAYS(WMLT_SOA_RESIZE)
        }
        if (needs.rectLights) {
            WMLT_PT_RECT_LIGHT_ARRAYS(WMLT_SOA_RESIZE)
        }
        if (needs.matte) {
            WMLT_PT_MATTE_ARRAYS(WMLT_SOA_RESIZE)
        }
        if (needs.media) {
            WMLT_PT_MEDIA_ARRAYS(WMLT_SOA_RESIZE)
        }
        if (needs.spectral) {
            WMLT_PT_SPECTRAL_ARRAYS(WMLT_SOA_RESIZE)
        }
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
// A spectral render's wavelengths read dimension kWavelengthDim (kernels/spectral.h).
constexpr uint32_t kBounceBase = 4;
constexpr uint32_t kBounceStride = 7;
inline uint32_t bounceDim(int depth, uint32_t j) { return kBounceBase + uint32_t(depth - 1) * kBounceStride + j; }

}  // namespace wmlt
