// The surface stage: turns Embree hits into shading data (position, normals, frame,
// material with its texture applied, from the normal or the regularized table). Shared by
// every tracer.
#pragma once
#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>

#include "kernels/bsdf.h"
#include "kernels/texture.h"
#include "scene/scene.h"
#include "scene/transform.h"
#include "stages/core/textures.h"

namespace wmlt {

struct SurfacePoint {
    Vec3 p;   // on the surface
    Vec3 ng;  // geometric normal, unit, outward (the loader's winding; spheres: outward)
    Vec3 ns;  // shading normal, unit, on ng's side
    float u = 0, v = 0;
    int material = -1;
    int light = -1;
    Vec3 dpdu;  // F::aniso only: dp/du (the bump's derivative), the anisotropic frame's x
};

// The scene's surface choices (SceneFeatures) as compile-time constants: the stages that
// resolve hits are instantiated per combination and choose one per stage call
// (withSurfaceFeatures), so no hit tests them.
//   Uv: the surface stage computes (u, v) (textures or bump); Bump: bump maps;
//   Textures: textured colour parameters; OneSided: materials black from below;
//   Aniso: some material is anisotropic, its hits' frames follow dp/du (shadingFrame).
template <bool Uv, bool Bump, bool Textures, bool OneSided, bool Aniso = false>
struct SurfaceFeatures {
    static constexpr bool uv = Uv, bump = Bump, textures = Textures, oneSided = OneSided, aniso = Aniso;
};

// Calls fn(F{}) with F the SurfaceFeatures of the scene.
template <bool... Chosen, class Fn>
void withBools(Fn&& fn) {
    fn(SurfaceFeatures<Chosen...>{});
}
template <bool... Chosen, class Fn, class... Rest>
void withBools(Fn&& fn, bool next, Rest... rest) {
    if (next) withBools<Chosen..., true>(fn, rest...);
    else withBools<Chosen..., false>(fn, rest...);
}
// A scene with anisotropic materials takes the one instantiation with every feature on
// (each tests its material's own fields, so it is right for any scene) and dp/du kept.
template <class Fn>
void withSurfaceFeatures(const SceneFeatures& f, Fn&& fn) {
    if (f.anisotropic) fn(SurfaceFeatures<true, true, true, true, true>{});
    else withBools(fn, f.needUv, f.bump, f.textures, f.oneSided);
}

// Helpers of surfaceAt (surface.cpp): partial derivatives of p in (u, v) on a triangle
// (pbrt-v4 6.5.3) and on the two kinds of sphere parametrisation, and the bump map.
void triangleDerivatives(const TriangleMesh& m, const uint32_t* tri, Vec3 ns, Vec3& dpdu, Vec3& dpdv);
void sphereDerivatives(const GeomRecord& g, Vec3 local, Vec3& dpdu, Vec3& dpdv);
void sphereDerivativesMitsuba(const GeomRecord& g, Vec3 l, Vec3& dpdu, Vec3& dpdv);
// (applyBump first resolves a blend of bump- or normal-mapped parts to the part choosePart
// gives at the hit: Scene::choosesPart.)
void applyBump(const Scene& scene, SurfacePoint& sp, Vec3 dpdu, Vec3 dpdv);
int choosePart(const Scene& scene, const SurfacePoint& sp);

// Called by a stage resolving hits i = 0 .. n - 1 of rays before it resolves hit i: starts
// loading what surfaceAt will read of hit i + 8 that is not in cache after traversal, its
// triangle's corner normals (on a large mesh, a miss on nearly every hit), so that the
// loads overlap.
inline void prefetchSurfaceAhead(const Scene& scene, const RTCRayHit* rays, size_t i, size_t n) {
    constexpr size_t kAhead = 8;
    if (i + kAhead >= n) return;
    const RTCRayHit& rh = rays[i + kAhead];
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return;
    const GeomRecord& g = scene.geoms[rh.hit.geomID];
    if (!g.cornerNormals.empty()) __builtin_prefetch(&g.cornerNormals[size_t(rh.hit.primID) * 3]);
}

// Geometry of a hit (rh must have hit something).
template <class F>
SurfacePoint surfaceAt(const Scene& scene, const RTCRayHit& rh) {
    const GeomRecord& g = scene.geoms[rh.hit.geomID];
    SurfacePoint sp;
    sp.material = g.material;
    sp.light = g.light;
    Vec3 o(rh.ray.org_x, rh.ray.org_y, rh.ray.org_z), d(rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z);
    if (g.kind == ShapeKind::Sphere) {
        Vec3 p = o + d * rh.ray.tfar;
        const Vec3 ng = normalize(p - g.center);
        sp.ng = ng;
        sp.p = g.center + ng * g.radius;  // re-projected onto the sphere
        sp.ns = ng;
        if constexpr (F::uv) {
            Vec3 l = normalize(g.toLocal.vector(sp.ng));
            const bool mitsuba = g.uv == UvKind::SphereMitsuba;
            if (mitsuba) {  // phi from +x towards +y about the +z pole, v = 0 at +z
                const float u = std::atan2(l.y, l.x) * kInv2Pi;
                sp.u = u < 0 ? u + 1.0f : u;
                sp.v = std::acos(std::clamp(l.z, -1.0f, 1.0f)) * kInvPi;
            } else {  // longitude from +x towards +z, latitude with v = 1 at the north pole (+y)
                sp.u = 0.5f + std::atan2(l.z, l.x) * kInv2Pi;
                sp.v = 1.0f - std::acos(std::clamp(l.y, -1.0f, 1.0f)) * kInvPi;
            }
            if (F::bump && sp.material >= 0) {
                Vec3 dpdu, dpdv;
                if (mitsuba) sphereDerivativesMitsuba(g, l, dpdu, dpdv);
                else sphereDerivatives(g, l, dpdu, dpdv);
                applyBump(scene, sp, dpdu, dpdv);
                if constexpr (F::aniso) sp.dpdu = dpdu;
            }
        }
        return sp;
    }
    const TriangleMesh& m = *g.mesh;
    const uint32_t* tri = &m.indices[size_t(rh.hit.primID) * 3];
    float b1 = rh.hit.u, b2 = rh.hit.v, b0 = 1.0f - b1 - b2;
    // Embree's Ng is cross(p1 - p0, p2 - p0) (the loader's outward winding), and the hit
    // point is o + t d: the vertex positions, no longer in cache after traversal (Embree's
    // BVH leaves hold copies), are not fetched again.
    sp.p = o + d * rh.ray.tfar;
    // A shape of a group, hit through an instance: Embree's Ng and the mesh are in the
    // group's coordinates (normals go to the world by the inverse transpose).
    const InstanceDesc* inst = rh.hit.instID[0] == RTC_INVALID_GEOMETRY_ID ? nullptr : &scene.instances[rh.hit.instID[0] - scene.firstInstanceID];
    Vec3 ngRaw(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
    if (inst) ngRaw = normalToWorld(inst->toLocal, ngRaw);
    // Both normals from the register: `sp.ns = sp.ng` read sp.ng back from memory across
    // two of its stores and stalled on store forwarding (a third of surfaceAt's samples).
    const Vec3 ng = normalize(ngRaw);
    sp.ng = ng;
    sp.ns = ng;
    if (!g.cornerNormals.empty()) {
        const Vec3* cn = &g.cornerNormals[size_t(rh.hit.primID) * 3];
        Vec3 ns = cn[0] * b0 + cn[1] * b1 + cn[2] * b2;
        if (inst) ns = normalToWorld(inst->toLocal, ns);
        float l2 = lengthSquared(ns);
        if (l2 > 0) {
            ns = ns / std::sqrt(l2);
            sp.ns = dot(ns, sp.ng) < 0 ? -ns : ns;
        }
    }
    if constexpr (F::uv) {
        if (!m.uvs.empty()) {
            const float* uv = m.uvs.data();
            sp.u = uv[2 * tri[0]] * b0 + uv[2 * tri[1]] * b1 + uv[2 * tri[2]] * b2;
            sp.v = uv[2 * tri[0] + 1] * b0 + uv[2 * tri[1] + 1] * b1 + uv[2 * tri[2] + 1] * b2;
        }
    }
    if constexpr (F::bump) {
        if (sp.material >= 0) {
            Vec3 dpdu, dpdv;
            if (!inst) {
                triangleDerivatives(m, tri, sp.ns, dpdu, dpdv);
            } else {  // in the group's coordinates, then to the world
                // (world to group: normalToWorld of the inverse pair, toWorld's transpose)
                triangleDerivatives(m, tri, normalize(normalToWorld(inst->toWorld, sp.ns)), dpdu, dpdv);
                dpdu = inst->toWorld.vector(dpdu);
                dpdv = inst->toWorld.vector(dpdv);
            }
            applyBump(scene, sp, dpdu, dpdv);
            if constexpr (F::aniso) sp.dpdu = dpdu;
        }
    }
    return sp;
}

// The material of a hit, written into out (a vertex's or hit's record): its constants
// (`table`: 0, or Scene::regularizedOffset for its regularized version, pbrt's regularize);
// seen from below its shading normal (wo, world, towards the previous vertex) a one-sided
// (Mitsuba) material is black. A material with textures is queued in jobs for the texture
// stage (textures.h, evaluateTextures), which finishes the record once the round's
// surfaces are resolved. In place, not returned: a BsdfParams built in registers and
// stored to the stack piece by piece, then copied out as one 64-byte load, stalled on
// store forwarding (24% of resolveBptHits on the seed room).
template <class F>
void materialAt(const Scene& scene, const SurfacePoint& sp, Vec3 wo, BsdfParams& out, TextureJobs& jobs, uint32_t table) {
    out = scene.materials[size_t(sp.material) + table];
    if constexpr (F::oneSided) {
        if (!scene.desc.materials[sp.material].twoSided && !(dot(wo, sp.ns) > 0)) {
            out = BsdfParams{};  // a black Matte: f = 0, every sample ends the path
            return;
        }
    }
    if constexpr (F::textures)
        if (scene.texturedMaterial[size_t(sp.material)]) jobs.add(&out, sp.material, sp.u, sp.v, sp.p, sp.ng);
}

// The shading frame of a hit: Frame::fromNormal, or, for an anisotropic material, x along
// dp/du made orthogonal to the shading normal (Mitsuba 3's convention: alpha_u along u; a
// mesh without (u, v) falls back to fromNormal's x, as triangleDerivatives does).
template <class F>
inline Frame shadingFrame(const Scene& scene, const SurfacePoint& sp) {
    if constexpr (F::aniso) {
        if (sp.material >= 0) {
            const BsdfExtra* x = scene.materials[sp.material].x;
            if (x && x->anisotropic) return Frame::fromNormalTangent(sp.ns, sp.dpdu);
        }
    }
    return Frame::fromNormal(sp.ns);
}

// Writes hit h of a batch (PT, LT: the same hit arrays) from path i's surface point:
// position, geometric normal, wo, shading frame and material (of `table`, as materialAt).
template <class F, class Batch>
inline void recordHit(const Scene& scene, Batch& b, size_t h, size_t i, const SurfacePoint& sp, Vec3 wo, uint32_t table) {
    b.hitPath[h] = uint32_t(i);
    b.p[h] = sp.p;
    b.ng[h] = sp.ng;
    b.wo[h] = wo;
    b.shading[h] = shadingFrame<F>(scene, sp);
    materialAt<F>(scene, sp, wo, b.bsdf[h], b.textureJobs, table);
}

}  // namespace wmlt
