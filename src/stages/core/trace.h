// The one place that calls Embree's traversal: batches of rays in, hits out. Kept
// behind this small interface because Embree 4 removed the stream API.
// Measured on this machine (../shared/spec/embree-streams.md): COHERENT streams pay
// 2x for camera rays in tile order and cost 2x on anything else; rtcOccluded1M beats a
// loop of rtcOccluded1 for shadow rays.
#pragma once
#include <embree3/rtcore.h>

#include <cstddef>

#include "wavemmlt/math.h"

namespace wmlt {

// Closest hits for n rays (in place). `coherent`: camera rays issued in tile order.
void traceClosest(RTCScene scene, RTCRayHit* rays, size_t n, bool coherent);
// Occlusion for n rays: tfar becomes -inf for each occluded ray.
void traceOccluded(RTCScene scene, RTCRay* rays, size_t n);

inline void setRay(RTCRay& r, Vec3 o, Vec3 d, float tnear, float tfar) {
    r.org_x = o.x;
    r.org_y = o.y;
    r.org_z = o.z;
    r.tnear = tnear;
    r.dir_x = d.x;
    r.dir_y = d.y;
    r.dir_z = d.z;
    r.time = 0;
    r.tfar = tfar;
    r.mask = 0xffffffffu;
    r.id = 0;
    r.flags = 0;
}
inline Vec3 rayDir(const RTCRayHit& r) { return {r.ray.dir_x, r.ray.dir_y, r.ray.dir_z}; }

inline void setRayHit(RTCRayHit& rh, Vec3 o, Vec3 d) {
    setRay(rh.ray, o, d, 0.0f, INFINITY);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

}  // namespace wmlt
