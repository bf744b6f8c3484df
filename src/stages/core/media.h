// The media stages' shared parts (docs/media.md), for every tracer whose batch has the media
// arrays (a path's `medium`, `mediumEvent`, `mediumT`; PT's and LT's): the free-path samples
// of a round's rays up to their hits, crossing pass-through boundaries (traverseMediaOf), and
// the transmittance of a shadow or connection ray through media and pass-through boundaries
// (transmittanceAlong, media.cpp).
#pragma once
#include <embree3/rtcore.h>

#include "kernels/medium.h"
#include "kernels/rng.h"
#include "scene/scene.h"
#include "stages/core/trace.h"
#include "stages/core/wave.h"

namespace wmlt {

// Bounce d's free-path sample on its k-th segment (k counts the pass-through boundaries
// crossed, below kMediumStride) reads its own range of dimensions, apart from the bounces'
// (a scene without media reads the same numbers as before media existed).
constexpr uint32_t kMediumBase = 1u << 24, kMediumStride = 256;
inline uint32_t mediumDim(int depth, uint32_t k) { return kMediumBase + uint32_t(depth - 1) * kMediumStride + k; }

// A hit's geometric normal in world space (unnormalised; rh must have hit something).
Vec3 hitNormal(const Scene& scene, const RTCRayHit& rh);
// The medium a ray along d is in after crossing the surface rh hit, from medium m.
int mediumAcross(const Scene& scene, const RTCRayHit& rh, Vec3 d, int m);
// Moves rh's ray to start just past the surface it hit, up to tMax.
void continuePast(const Scene& scene, RTCRayHit& rh, float tMax);

// Each path's free-path sample in its medium up to its hit (beta times its weight): a
// scattering event (mediumEvent, mediumT along the ray as it ends) or the surface, crossing
// pass-through boundaries (the medium updated, the ray continued past them).
template <class Batch>
void traverseMediaOf(const Scene& scene, Batch& b, int depth, RayCounters& c) {
    for (size_t i = 0; i < b.numPaths; ++i) {
        RTCRayHit& rh = b.ray[i];
        const uint64_t key = b.key[b.pathSlot[i]];
        int m = b.medium[i];
        b.mediumEvent[i] = 0;
        for (uint32_t k = 0;; ++k) {
            const bool hit = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
            if (m >= 0) {
                const Vec3 o(rh.ray.org_x, rh.ray.org_y, rh.ray.org_z), d(rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z);
                const uint32_t dim = mediumDim(depth, k);  // a grid's stream is seeded from it too
                const FreePath fp = sampleMediumFreePath(scene.media[size_t(m)], o, d, hit ? rh.ray.tfar : INFINITY,
                                                         sampleDimension(key, dim), mix64(key ^ (uint64_t(dim) << 32)));
                b.beta[i] = b.beta[i] * fp.weight;
                if (fp.scattered) {
                    b.mediumEvent[i] = 1;
                    b.mediumT[i] = fp.t;
                    break;
                }
            }
            if (!hit || !scene.geoms[rh.hit.geomID].passThrough) break;
            if (k + 1 >= kMediumStride) {  // a ray through hundreds of boundaries: dropped
                b.beta[i] = Vec3(0.0f);
                break;
            }
            const Vec3 d(rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z);
            m = mediumAcross(scene, rh, d, m);
            continuePast(scene, rh, INFINITY);
            traceClosest(scene.rtc, &rh, 1, false);
            ++c.raysIntersect;
        }
        b.medium[i] = m;
    }
}

// Hit h of a batch with the hit-surface and media arrays (PT's, LT's): path i's scattering
// event in its medium, at mediumT along its ray: a Phase vertex (kernels/bsdf.h) with no
// normal (rays leave it without offset), its frame's z towards the previous vertex.
template <class Batch>
void recordMediumVertex(const Scene& scene, Batch& b, size_t h, size_t i) {
    const RTCRayHit& rh = b.ray[i];
    const Vec3 d = rayDir(rh);
    const int m = b.medium[i];
    b.hitPath[h] = uint32_t(i);
    b.p[h] = Vec3(rh.ray.org_x, rh.ray.org_y, rh.ray.org_z) + d * b.mediumT[i];
    b.ng[h] = Vec3(0.0f);
    b.wo[h] = -d;
    b.shading[h] = Frame::fromNormal(-d);
    b.bsdf[h] = BsdfParams{};
    b.bsdf[h].kind = MaterialKind::Phase;
    b.bsdf[h].eta = scene.media[size_t(m)].g;  // phaseG
    b.hitMediumIn[h] = b.hitMediumOut[h] = m;
}

// The transmittance along ray r (up to its tfar) from medium m through media and
// pass-through boundaries; 0 when any other surface is in the way. A grid's ratio tracking
// reads streams seeded by seed and the segment.
Vec3 transmittanceAlong(const Scene& scene, const RTCRay& r, int m, uint64_t seed, RayCounters& c);

}  // namespace wmlt
