// Structure-of-arrays state of one batch of path-tracing samples (a tile of pixels times
// a range of sample indices). Three groups of arrays, each compacted in order:
//   slots  - one per sample, for the life of the batch: pixel, random key, radiance L;
//   paths  - the live paths of the current bounce: their ray, throughput, MIS data;
//   hits   - the live paths that hit a surface this bounce: the surface and material.
// Every round of the wavefront reads one group and writes the next (docs/architecture.md).
#pragma once
#include <embree3/rtcore.h>

#include <cstdint>
#include <vector>

#include "kernels/bsdf.h"
#include "stages/film.h"

namespace wmlt {

struct PtBatch {
    // Slots.
    std::vector<uint32_t> pixel;
    std::vector<uint64_t> key;
    std::vector<Vec3> L;

    // Per batch: NaN or Inf contributions (left out), luminance by path length.
    uint64_t nonfinite = 0;
    PathLengthSums lengths;

    // Live paths (index i < numPaths).
    size_t numPaths = 0;
    std::vector<uint32_t> pathSlot;
    std::vector<RTCRayHit> ray;
    std::vector<Vec3> beta;          // throughput
    std::vector<float> prevPdf;      // solid-angle pdf of the BSDF sample that made the ray
    std::vector<uint8_t> prevDelta;  // ... which was a delta lobe: no MIS on what it hits

    // Surface hits (index h < numHits), in path order.
    size_t numHits = 0;
    std::vector<uint32_t> hitPath;   // index into the live paths
    std::vector<Vec3> p, ng, wo;     // position, geometric normal (outward), -ray direction
    std::vector<Frame> shading;      // shading frame, n = shading normal (outward)
    std::vector<BsdfParams> bsdf;
    // Hits grouped by material kind: order[kindStart[k] .. kindStart[k+1]).
    std::vector<uint32_t> order;
    uint32_t kindStart[kMaterialKinds + 1] = {};

    // Shadow rays of next-event estimation.
    size_t numShadow = 0;
    std::vector<RTCRay> shadow;
    std::vector<uint32_t> shadowSlot;
    std::vector<Vec3> shadowL;       // unoccluded contribution

    // Next bounce, written by BSDF sampling at the hit's index (alive[h] = 0: ended).
    std::vector<uint8_t> alive;
    std::vector<Vec3> nextDir, nextBeta;
    std::vector<float> nextPdf;
    std::vector<uint8_t> nextDelta;

    void reserve(size_t n) {
        pixel.resize(n); key.resize(n); L.resize(n);
        pathSlot.resize(n); ray.resize(n); beta.resize(n); prevPdf.resize(n); prevDelta.resize(n);
        hitPath.resize(n); p.resize(n); ng.resize(n); wo.resize(n); shading.resize(n);
        bsdf.resize(n); order.resize(n);
        shadow.resize(n); shadowSlot.resize(n); shadowL.resize(n);
        alive.resize(n); nextDir.resize(n); nextBeta.resize(n); nextPdf.resize(n); nextDelta.resize(n);
    }
};

// Primary sample layout of a path-tracing sample (see rng.h): dimensions 0-1 jitter the
// pixel position within its stratum, 2-3 pick the lens point, and bounce d >= 1 reads
// dimensions kBounceBase + (d - 1) * kBounceStride + (0: light choice, 1-2: light point,
// 3: BSDF lobe, 4-5: BSDF direction, 6: Russian roulette).
constexpr uint32_t kBounceBase = 4;
constexpr uint32_t kBounceStride = 7;
inline uint32_t bounceDim(int depth, uint32_t j) { return kBounceBase + uint32_t(depth - 1) * kBounceStride + j; }

}  // namespace wmlt
