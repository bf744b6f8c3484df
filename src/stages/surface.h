// The surface stage: turns Embree hits into shading data (position, normals, frame,
// material with its texture applied). Shared by every tracer.
#pragma once
#include <embree3/rtcore.h>

#include "kernels/bsdf.h"
#include "scene/scene.h"

namespace wmlt {

struct SurfacePoint {
    Vec3 p;       // on the surface
    Vec3 ng;      // geometric normal, unit, outward (the loader's winding; spheres: outward)
    Vec3 ns;      // shading normal, unit, on ng's side
    float u = 0, v = 0;
    int material = -1;
    int light = -1;
};

// Geometry of a hit (rh must have hit something).
SurfacePoint surfaceAt(const Scene& scene, const RTCRayHit& rh);

// The material of a hit with textures applied (the scene's features decide, per scene,
// whether textures are looked up at all). wo (world, towards the previous vertex) decides
// the side of a one-sided (Mitsuba) material: seen from below its shading normal it is black.
BsdfParams materialAt(const Scene& scene, const SurfacePoint& sp, Vec3 wo);

// Writes hit h of a batch (PT, LT: the same hit arrays) from path i's surface point:
// position, geometric normal, wo, shading frame and material.
template <class Batch>
inline void recordHit(const Scene& scene, Batch& b, size_t h, size_t i, const SurfacePoint& sp, Vec3 wo) {
    b.hitPath[h] = uint32_t(i);
    b.p[h] = sp.p;
    b.ng[h] = sp.ng;
    b.wo[h] = wo;
    b.shading[h] = Frame::fromNormal(sp.ns);
    b.bsdf[h] = materialAt(scene, sp, wo);
}

// Samples the BSDF B of hit h (recordHit's arrays) with numbers ul (lobe), u1, u2: s in
// the hit's shading frame; false when there is no usable sample (pdf 0 or f black).
template <class B, class Batch>
inline bool sampleHitBsdf(const Batch& b, uint32_t h, float ul, float u1, float u2, TransportMode mode, BsdfSample& s) {
    const Vec3 wo = b.shading[h].toLocal(b.wo[h]);
    return B::sample(b.bsdf[h], wo, ul, u1, u2, mode, s) && s.pdf > 0 && !isBlack(s.f);
}

}  // namespace wmlt
