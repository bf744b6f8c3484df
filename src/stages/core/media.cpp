#include "stages/core/media.h"

namespace wmlt {

int mediumAcross(const Scene& scene, const RTCRayHit& rh, Vec3 d, int m) {
    const GeomRecord& g = scene.geoms[rh.hit.geomID];
    if (!g.mediumBoundary) return m;
    return dot(d, scene.hitNormal(rh)) < 0 ? g.mediumInside : g.mediumOutside;
}

void continuePast(const Scene& scene, RTCRayHit& rh, float tMax) {
    const Vec3 o(rh.ray.org_x, rh.ray.org_y, rh.ray.org_z), d(rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z);
    const Vec3 p = o + d * rh.ray.tfar;
    const Vec3 origin = scene.offsetRayOrigin(p, normalize(scene.hitNormal(rh)), d);
    setRayHit(rh, origin, d);
    rh.ray.tfar = tMax;
}

namespace {

// transmittanceAlong's walk; with Densities also each segment's free-path densities (the
// segment next to each end ending in the medium there when that end is a medium vertex).
template <bool Densities>
Vec3 transmittanceOf(const Scene& scene, const PathMedia& media, const RTCRay& r, int m, uint64_t seed, bool fromInMedium, bool toInMedium,
                     SegmentDensities& rho, RayCounters& c) {
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
        const bool last = rh.hit.geomID == RTC_INVALID_GEOMETRY_ID;
        if (!last && !scene.geoms[rh.hit.geomID].passThrough) return Vec3(0.0f);  // occluded
        const float len = last ? remaining : rh.ray.tfar;
        if (m >= 0) {
            const Medium med = media[m];
            T = T * mediumTransmittance(med, o, d, len, mix64(seed + k));
            if constexpr (Densities) {
                rho.fwd *= freePathDensity(med, len, last && toInMedium);
                rho.rev *= freePathDensity(med, len, k == 0 && fromInMedium);
            }
        }
        if (last) return T;
        remaining -= rh.ray.tfar;
        m = mediumAcross(scene, rh, d, m);
        continuePast(scene, rh, remaining);
    }
    return Vec3(0.0f);
}

}  // namespace

Vec3 transmittanceAlong(const Scene& scene, const PathMedia& media, const RTCRay& r, int m, uint64_t seed, RayCounters& c) {
    SegmentDensities unused;
    return transmittanceOf<false>(scene, media, r, m, seed, false, false, unused, c);
}

Vec3 transmittanceAlong(const Scene& scene, const PathMedia& media, const RTCRay& r, int m, uint64_t seed, bool fromInMedium, bool toInMedium,
                        SegmentDensities& rho, RayCounters& c) {
    return transmittanceOf<true>(scene, media, r, m, seed, fromInMedium, toInMedium, rho, c);
}

}  // namespace wmlt
