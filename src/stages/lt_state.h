// Structure-of-arrays state of one batch of light-tracing samples (a tile of pixels
// times a range of sample indices: one light subpath per pixel sample). As in the path
// tracer (pt_state.h), groups of arrays compacted in order:
//   slots   - one per light subpath: its random key and initial throughput scale;
//   paths   - the live subpaths of the current round: ray, throughput beta;
//   hits    - the live subpaths that hit a scattering surface: surface and material;
//   conns   - camera connections (t = 1): a shadow ray to the lens and its splat;
//   splats  - this batch's unoccluded contributions, in stage order (film.h).
#pragma once
#include <embree3/rtcore.h>

#include <cstdint>
#include <vector>

#include "kernels/bsdf.h"
#include "stages/film.h"

namespace wmlt {

struct LtBatch {
    // Slots.
    std::vector<uint64_t> key;
    std::vector<float> betaScale;    // max component of the initial beta (Russian roulette)

    // Live paths (index i < numPaths).
    size_t numPaths = 0;
    std::vector<uint32_t> pathSlot;
    std::vector<RTCRayHit> ray;
    std::vector<Vec3> beta;          // throughput: flux-like, Le |cos| / (pmf pdfPos pdfDir) ...

    // Surface hits (index h < numHits), in path order.
    size_t numHits = 0;
    std::vector<uint32_t> hitPath;
    std::vector<Vec3> p, ng, wo;     // wo: towards the previous vertex (the light side)
    std::vector<Frame> shading;
    std::vector<BsdfParams> bsdf;
    std::vector<uint32_t> order;
    uint32_t kindStart[kMaterialKinds + 1] = {};

    // Camera connections (index c < numConn).
    size_t numConn = 0;
    std::vector<RTCRay> conn;
    std::vector<uint32_t> connPixel;
    std::vector<Vec3> connValue;     // unoccluded splat value

    // Next round, written by BSDF sampling at the hit's index.
    std::vector<uint8_t> alive;
    std::vector<Vec3> nextDir, nextBeta;

    std::vector<Splat> splats;
    uint64_t nonfinite = 0;          // splats discarded as NaN or Inf
    PathLengthSums lengths;          // luminance of the splats by path length

    void reserve(size_t n) {
        key.resize(n); betaScale.resize(n);
        pathSlot.resize(n); ray.resize(n); beta.resize(n);
        hitPath.resize(n); p.resize(n); ng.resize(n); wo.resize(n); shading.resize(n);
        bsdf.resize(n); order.resize(n);
        conn.resize(n); connPixel.resize(n); connValue.resize(n);
        alive.resize(n); nextDir.resize(n); nextBeta.resize(n);
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
