// The path tracer's media stages (docs/media.md), run only for a scene with media or
// pass-through boundaries (SceneFeatures::media): traverseMedia after each intersect,
// traceShadowsThroughMedia instead of traceShadows.
#include "kernels/medium.h"
#include "kernels/rng.h"
#include "scene/transform.h"
#include "stages/pt_stages.h"
#include "stages/trace.h"

namespace wmlt {

namespace {

// A hit's geometric normal in world space (unnormalised; rh must have hit something).
Vec3 hitNormal(const Scene& scene, const RTCRayHit& rh) {
    const GeomRecord& g = scene.geoms[rh.hit.geomID];
    if (g.kind == ShapeKind::Sphere) {
        const Vec3 p(rh.ray.org_x + rh.ray.dir_x * rh.ray.tfar, rh.ray.org_y + rh.ray.dir_y * rh.ray.tfar,
                     rh.ray.org_z + rh.ray.dir_z * rh.ray.tfar);
        return p - g.center;
    }
    const Vec3 n(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
    if (rh.hit.instID[0] == RTC_INVALID_GEOMETRY_ID) return n;
    return normalToWorld(scene.instances[rh.hit.instID[0] - scene.firstInstanceID].toLocal, n);
}

// The medium a ray along d is in after crossing the surface rh hit, from medium m.
inline int mediumAcross(const Scene& scene, const RTCRayHit& rh, Vec3 d, int m) {
    const GeomRecord& g = scene.geoms[rh.hit.geomID];
    if (!g.mediumBoundary) return m;
    return dot(d, hitNormal(scene, rh)) < 0 ? g.mediumInside : g.mediumOutside;
}

// Moves rh's ray to start just past the surface it hit, unbounded (or up to tMax).
inline void continuePast(const Scene& scene, RTCRayHit& rh, float tMax) {
    const Vec3 o(rh.ray.org_x, rh.ray.org_y, rh.ray.org_z), d(rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z);
    const Vec3 p = o + d * rh.ray.tfar;
    const Vec3 origin = scene.offsetRayOrigin(p, normalize(hitNormal(scene, rh)), d);
    setRayHit(rh, origin, d);
    rh.ray.tfar = tMax;
}

}  // namespace

void traverseMedia(const Scene& scene, PtBatch& b, int depth, RayCounters& c) {
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

void traceShadowsThroughMedia(const Scene& scene, PtBatch& b, int length, RayCounters& c) {
    for (size_t i = 0; i < b.numShadow; ++i) {
        const RTCRay& r = b.shadow[i];
        // a grid's ratio tracking: a stream per shadow ray and segment, apart from the paths'
        const uint64_t seed = mix64(b.key[b.shadowSlot[i]] ^ 0x5348414430ull ^ (uint64_t(length) << 40));
        const Vec3 d(r.dir_x, r.dir_y, r.dir_z);
        RTCRayHit rh;
        setRayHit(rh, Vec3(r.org_x, r.org_y, r.org_z), d);
        rh.ray.tnear = r.tnear;
        rh.ray.tfar = r.tfar;
        int m = b.shadowMedium[i];
        float remaining = r.tfar;
        Vec3 T(1.0f);
        bool reached = false;
        for (uint32_t k = 0; k < kMediumStride; ++k) {
            traceClosest(scene.rtc, &rh, 1, false);
            ++c.raysOccluded;
            const Vec3 o(rh.ray.org_x, rh.ray.org_y, rh.ray.org_z);
            if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
                if (m >= 0) T = T * mediumTransmittance(scene.media[size_t(m)], o, d, remaining, mix64(seed + k));
                reached = true;
                break;
            }
            if (!scene.geoms[rh.hit.geomID].passThrough) break;  // occluded
            if (m >= 0) T = T * mediumTransmittance(scene.media[size_t(m)], o, d, rh.ray.tfar, mix64(seed + k));
            remaining -= rh.ray.tfar;
            m = mediumAcross(scene, rh, d, m);
            continuePast(scene, rh, remaining);
        }
        if (reached && !isBlack(T)) addRadiance(b, b.shadowSlot[i], b.shadowL[i] * T, length);
    }
}

}  // namespace wmlt
