#include "stages/core/surface.h"

#include <cstring>

#include "kernels/bump.h"
#include "kernels/rng.h"

namespace wmlt {

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

// A blend resolved per hit (Scene::choosesPart: pbrt's mix, bump- or normal-mapped parts) is part 1 where a hash of the
// hit point is below its weight there, else part 0: pbrt-v4's mix, which chooses one
// material per hit for every mix, by a hash of the point (and wo: here the point alone, so
// that a camera and a light subpath see the same part at a point).
int choosePart(const Scene& scene, const SurfacePoint& sp) {
    const MaterialDesc& m = scene.desc.materials[size_t(sp.material)];
    float w = m.blendWeight;
    if (const int t = m.texture[MaterialParam::BlendWeight]; t >= 0)
        w = std::clamp(w * luminance(evalTextureOf(scene.desc.textures, size_t(t), sp.u, sp.v, sp.p, sp.ng)), 0.0f, 1.0f);
    uint32_t bits[3];
    std::memcpy(bits, &sp.p, sizeof bits);
    const uint64_t h = mix64(mix64(mix64(uint64_t(bits[0]) << 32 | bits[1]) ^ bits[2]) ^ uint64_t(sp.material));
    const float u = float(h >> 40) * 0x1p-24f;
    return m.blendPart[u < w ? 1 : 0];
}

void applyBump(const Scene& scene, SurfacePoint& sp, Vec3 dpdu, Vec3 dpdv) {
    if (scene.choosesPart[size_t(sp.material)]) sp.material = choosePart(scene, sp);
    const MaterialDesc& m = scene.desc.materials[sp.material];
    if (m.normalMap >= 0) {
        sp.ns = normalMapped(scene.desc.textures, size_t(m.normalMap), sp.u, sp.v, sp.p, sp.ns, sp.ng, dpdu);
        return;
    }
    if (m.bump < 0) return;
    if (m.bumpMitsuba) sp.ns = bumpedNormalMitsuba(scene.desc.textures[m.bump], m.bumpScale, sp.u, sp.v, sp.ns, sp.ng, dpdu, dpdv);
    else if (m.bumpPbrt) sp.ns = bumpedNormalPbrt(heightOf(scene.desc.textures, size_t(m.bump), sp.ng), sp.p, sp.u, sp.v, sp.ns, sp.ng, dpdu, dpdv);
    else sp.ns = bumpedNormalBy(heightOf(scene.desc.textures, size_t(m.bump), sp.ng), sp.p, sp.u, sp.v, sp.ns, dpdu, dpdv);
}

}  // namespace wmlt
