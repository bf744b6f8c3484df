#include "stages/core/media.h"

#include "scene/transform.h"

namespace wmlt {

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

int mediumAcross(const Scene& scene, const RTCRayHit& rh, Vec3 d, int m) {
    const GeomRecord& g = scene.geoms[rh.hit.geomID];
    if (!g.mediumBoundary) return m;
    return dot(d, hitNormal(scene, rh)) < 0 ? g.mediumInside : g.mediumOutside;
}

void continuePast(const Scene& scene, RTCRayHit& rh, float tMax) {
    const Vec3 o(rh.ray.org_x, rh.ray.org_y, rh.ray.org_z), d(rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z);
    const Vec3 p = o + d * rh.ray.tfar;
    const Vec3 origin = scene.offsetRayOrigin(p, normalize(hitNormal(scene, rh)), d);
    setRayHit(rh, origin, d);
    rh.ray.tfar = tMax;
}

Vec3 transmittanceAlong(const Scene& scene, const RTCRay& r, int m, uint64_t seed, RayCounters& c) {
    const Vec3 d(r.dir_x, r.dir_y, r.dir_z);
    RTCRayHit rh;
    setRayHit(rh, Vec3(r.org_x, r.org_y, r.org_z), d);
    rh.ray.tnear = r.tnear;
    rh.ray.tfar = r.tfar;
    float remaining = r.tfar;
    Vec3 T(1.0f);
    for (uint32_t k = 0; k < kMediumStride; ++k) {
        traceClosest(scene.rtc, &rh, 1, false);
        ++c.raysOccluded;
        const Vec3 o(rh.ray.org_x, rh.ray.org_y, rh.ray.org_z);
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
            if (m >= 0) T = T * mediumTransmittance(scene.media[size_t(m)], o, d, remaining, mix64(seed + k));
            return T;
        }
        if (!scene.geoms[rh.hit.geomID].passThrough) return Vec3(0.0f);  // occluded
        if (m >= 0) T = T * mediumTransmittance(scene.media[size_t(m)], o, d, rh.ray.tfar, mix64(seed + k));
        remaining -= rh.ray.tfar;
        m = mediumAcross(scene, rh, d, m);
        continuePast(scene, rh, remaining);
    }
    return Vec3(0.0f);
}

}  // namespace wmlt
