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

}  // namespace wmlt
