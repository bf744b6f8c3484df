#include "stages/surface.h"

#include "kernels/bump.h"

namespace wmlt {

namespace {

// Partial derivatives of p with respect to (u, v) on a triangle (pbrt-v4 6.5.3); an
// arbitrary tangent frame where the triangle has no usable (u, v).
void triangleDerivatives(const TriangleMesh& m, const uint32_t* tri, Vec3 ns, Vec3& dpdu, Vec3& dpdv) {
    if (!m.uvs.empty()) {
        const float* uv = m.uvs.data();
        float du02 = uv[2 * tri[0]] - uv[2 * tri[2]], dv02 = uv[2 * tri[0] + 1] - uv[2 * tri[2] + 1];
        float du12 = uv[2 * tri[1]] - uv[2 * tri[2]], dv12 = uv[2 * tri[1] + 1] - uv[2 * tri[2] + 1];
        Vec3 dp02 = m.positions[tri[0]] - m.positions[tri[2]], dp12 = m.positions[tri[1]] - m.positions[tri[2]];
        float det = du02 * dv12 - dv02 * du12;
        if (std::fabs(det) > 1e-12f) {
            float inv = 1.0f / det;
            dpdu = (dp02 * dv12 - dp12 * dv02) * inv;
            dpdv = (dp12 * du02 - dp02 * du12) * inv;
            if (lengthSquared(cross(dpdu, dpdv)) > 0) return;
        }
    }
    Frame f = Frame::fromNormal(ns);
    dpdu = f.s;
    dpdv = f.t;
}

// The sphere's (u, v) of surfaceAt: u = 0.5 + phi / 2pi, v = 1 - theta / pi.
void sphereDerivatives(const GeomRecord& g, Vec3 local, Vec3& dpdu, Vec3& dpdv) {
    float phi = std::atan2(local.z, local.x);
    float cosT = std::clamp(local.y, -1.0f, 1.0f), sinT = std::sqrt(std::max(0.0f, 1.0f - cosT * cosT));
    float r = g.radius;
    dpdu = g.toWorld.vector(Vec3(-std::sin(phi), 0, std::cos(phi)) * (2.0f * kPi * r * sinT));
    dpdv = g.toWorld.vector(Vec3(cosT * std::cos(phi), -sinT, cosT * std::sin(phi)) * (-kPi * r));
}

// Mitsuba's sphere (u, v) = (phi / 2 pi, theta / pi) about local +z (l: the local unit
// normal), and its derivatives through the sphere's toWorld (which maps the unit sphere).
void sphereDerivativesMitsuba(const GeomRecord& g, Vec3 l, Vec3& dpdu, Vec3& dpdv) {
    const float phi = std::atan2(l.y, l.x), cosT = std::clamp(l.z, -1.0f, 1.0f);
    const float sinT = std::sqrt(std::max(0.0f, 1.0f - cosT * cosT));
    dpdu = g.toWorld.vector(Vec3(-std::sin(phi), std::cos(phi), 0) * (2.0f * kPi * sinT));
    dpdv = g.toWorld.vector(Vec3(cosT * std::cos(phi), cosT * std::sin(phi), -sinT) * kPi);
}

void applyBump(const Scene& scene, SurfacePoint& sp, Vec3 dpdu, Vec3 dpdv) {
    const MaterialDesc& m = scene.desc.materials[sp.material];
    if (m.bump < 0) return;
    if (m.bumpMitsuba)
        sp.ns = bumpedNormalMitsuba(scene.desc.textures[m.bump], m.bumpScale, sp.u, sp.v, sp.ns, sp.ng, dpdu, dpdv);
    else
        sp.ns = bumpedNormal(scene.desc.textures[m.bump], sp.p, sp.u, sp.v, sp.ns, dpdu, dpdv);
}

}  // namespace

SurfacePoint surfaceAt(const Scene& scene, const RTCRayHit& rh) {
    const GeomRecord& g = scene.geoms[rh.hit.geomID];
    SurfacePoint sp;
    sp.material = g.material;
    sp.light = g.light;
    Vec3 o(rh.ray.org_x, rh.ray.org_y, rh.ray.org_z), d(rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z);
    if (g.kind == ShapeKind::Sphere) {
        Vec3 p = o + d * rh.ray.tfar;
        sp.ng = normalize(p - g.center);
        sp.p = g.center + sp.ng * g.radius;  // re-projected onto the sphere
        sp.ns = sp.ng;
        if (scene.features.needUv) {
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
            if (scene.features.bump && sp.material >= 0) {
                Vec3 dpdu, dpdv;
                if (mitsuba) sphereDerivativesMitsuba(g, l, dpdu, dpdv);
                else sphereDerivatives(g, l, dpdu, dpdv);
                applyBump(scene, sp, dpdu, dpdv);
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
    sp.ng = normalize(Vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z));
    sp.ns = sp.ng;
    if (!g.cornerNormals.empty()) {
        const Vec3* cn = &g.cornerNormals[size_t(rh.hit.primID) * 3];
        Vec3 ns = cn[0] * b0 + cn[1] * b1 + cn[2] * b2;
        float l2 = lengthSquared(ns);
        if (l2 > 0) {
            ns = ns / std::sqrt(l2);
            sp.ns = dot(ns, sp.ng) < 0 ? -ns : ns;
        }
    }
    if (scene.features.needUv && !m.uvs.empty()) {
        const float* uv = m.uvs.data();
        sp.u = uv[2 * tri[0]] * b0 + uv[2 * tri[1]] * b1 + uv[2 * tri[2]] * b2;
        sp.v = uv[2 * tri[0] + 1] * b0 + uv[2 * tri[1] + 1] * b1 + uv[2 * tri[2] + 1] * b2;
    }
    if (scene.features.bump && sp.material >= 0) {
        Vec3 dpdu, dpdv;
        triangleDerivatives(m, tri, sp.ns, dpdu, dpdv);
        applyBump(scene, sp, dpdu, dpdv);
    }
    return sp;
}

BsdfParams materialAt(const Scene& scene, const SurfacePoint& sp, Vec3 wo) {
    BsdfParams b = scene.materials[sp.material];
    const MaterialDesc& m = scene.desc.materials[sp.material];
    if (scene.features.oneSided && !m.twoSided && !(dot(wo, sp.ns) > 0)) {
        BsdfParams black;  // a black Matte: f = 0, every sample ends the path
        return black;
    }
    if (scene.features.textures && m.texture >= 0)
        b.diffuse = b.diffuse * evalTexture(scene.desc.textures[m.texture], sp.u, sp.v, sp.p);
    return b;
}

}  // namespace wmlt
