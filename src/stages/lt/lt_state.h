// Structure-of-arrays state of one batch of light-tracing samples (a tile of pixels
// times a range of sample indices: one light subpath per pixel sample): a PathWave
// (wave.h: the live subpaths and their hits) and
//   slots   - one per light subpath: its random key and initial throughput scale;
//   paths   - per live subpath: its throughput beta (compacted with the wave);
//   hits    - per hit: the surface (WMLT_HIT_SURFACE_ARRAYS; wo points to the light side)
//             and the next throughput;
//   conns   - camera connections (t = 1): a shadow ray to the lens and its splat;
//   splats  - this batch's unoccluded contributions, in stage order (film.h).
#pragma once
#include <embree3/rtcore.h>

#include <cstdint>
#include <vector>

#include "kernels/bsdf.h"
#include "scene/scene_spectra.h"
#include "stages/core/film.h"
#include "stages/core/wave.h"

namespace wmlt {

// Per slot (one per light subpath):
//   key: its random key (ltSampleKey; dimensions: ltVertexDim below)
//   betaScale: the max component of its initial beta (Russian roulette)
// Per live path:
//   beta: its flux-like throughput: Le |cos| / (pmf pdfPos pdfDir), times f |cos| / pdf per bounce
// Per hit:
//   WMLT_HIT_SURFACE_ARRAYS: the surface (wave.h; wo points to the light side)
//   nextBeta: the throughput after the hit's BSDF sample
// Per camera connection (t = 1):
//   conn: its shadow ray to the lens
//   connPixel: the pixel it lands in, or kFilmPoint
//   connX, connY: its film point (kFilmPoint: spread about it, pushSplat)
//   connValue: its unoccluded splat
// clang-format off
#define WMLT_LT_ARRAYS(X)                                                                    \
    X(uint64_t, key) X(float, betaScale) X(Vec3, beta) WMLT_HIT_SURFACE_ARRAYS(X)          \
    X(Vec3, nextBeta) X(RTCRay, conn) X(uint32_t, connPixel) X(float, connX) X(float, connY) X(Vec3, connValue)
// clang-format on

// Allocated only for a scene with media (docs/media.md):
//   medium: per path, its medium
//   mediumEvent: this round's scattering event (traverseMediaOf)
//   mediumT: where
//   hitMediumIn, hitMediumOut: per hit, the media on its two sides
//   connMedium: per connection, the medium it starts in
//   connKey: its sample's key (a grid's ratio tracking)
// clang-format off
#define WMLT_LT_MEDIA_ARRAYS(X)                                                              \
    X(int32_t, medium) X(uint8_t, mediumEvent) X(float, mediumT) X(int32_t, hitMediumIn)   \
    X(int32_t, hitMediumOut) X(int32_t, connMedium) X(uint64_t, connKey)
// clang-format on

// Allocated only for a spectral render (RenderOptions::spectral; docs/spectral.md):
//   lambda: per slot, its wavelengths (the colour channels' meaning)
//   hitMaterial: per hit, its material (SceneDesc::materials; -1: a medium vertex)
//   connLambda: per camera connection, its path's wavelengths (connValue is at them until
//               its splat, which is the film's sRGB)
#define WMLT_LT_SPECTRAL_ARRAYS(X) X(Wavelengths, lambda) X(int32_t, hitMaterial) X(Wavelengths, connLambda)

struct LtBatch : PathWave {
    WMLT_LT_ARRAYS(WMLT_SOA_ARRAY)
    WMLT_LT_MEDIA_ARRAYS(WMLT_SOA_ARRAY)
    WMLT_LT_SPECTRAL_ARRAYS(WMLT_SOA_ARRAY)
    const SpectralScene* spectra = nullptr;  // a spectral render's (chosen once per render); nullptr: RGB
    size_t numConn = 0;
    std::vector<Splat> splats;
    std::vector<PointSplat> points;  // filtered scenes: contributions at film points
    ContributionTally tally;         // of the splats

    void reserve(size_t n, const BatchNeeds& needs) {
        resizeWave(n, needs);
        WMLT_LT_ARRAYS(WMLT_SOA_RESIZE)
        if (needs.media) {
            WMLT_LT_MEDIA_ARRAYS(WMLT_SOA_RESIZE)
        }
        if (needs.spectral) {
            WMLT_LT_SPECTRAL_ARRAYS(WMLT_SOA_RESIZE)
        }
        splats.reserve(n);
    }
};

// Primary sample layout of a light-tracing sample (keys: ltSampleKey, a stream apart
// from the path tracer's):
//   0: light choice, 1-2: point on the light, 3-4: emitted direction,
//   5-6: lens point of the light point's camera connection (length 1, area lights),
//   7-8: pixel jitter and 9-10: lens point of the camera ray that sees the environment
//        directly (length 1; a point at infinity cannot be connected to),
//   vertex d >= 1 (after d segments) reads kLtVertexBase + (d - 1) * kLtVertexStride +
//   (0-1: lens point of its camera connection, 2: BSDF lobe, 3-4: BSDF direction,
//   5: Russian roulette).
constexpr uint32_t kLtVertexBase = 11;
constexpr uint32_t kLtVertexStride = 6;
inline uint32_t ltVertexDim(int d, uint32_t j) { return kLtVertexBase + uint32_t(d - 1) * kLtVertexStride + j; }

}  // namespace wmlt
