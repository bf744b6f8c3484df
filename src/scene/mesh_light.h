// A triangle mesh emitter (LightType::Mesh): its triangles chosen in proportion to their
// areas, a uniform point in the chosen one (area density 1 / area). A textured one
// (LightDesc::texture: radiance L T(u, v)) is sampled by the texture's luminance instead:
//   - a triangle t in proportion to area_t times the mean luminance of T over it;
//   - in t, a point through the square-to-triangle warp (sampleUniformTriangle, which keeps
//     area) from a piecewise-constant density over an n x n grid of the warp's square, each
//     cell weighted by the mean luminance of T over it (n from the texels t covers, <= 64;
//     1 in meshes of more than 4096 triangles, whose triangles are fine enough a grid);
//   - area density pdfA = P(t) pdf2(a, b) / area_t, (a, b) the point's place in t's square.
// Cell means are estimated from 3 x 3 points and floored at 1/10 of the light's mean
// (defensive sampling): every point where T > 0 has a positive density (an unbiased sampler
// for any texture), and a bright sliver the points missed costs at most 10 / T's mean
// times its T (no fireflies; with 1e-3 a checkerboard's E[T / pdfA] converged visibly low).
#pragma once
#include <vector>

#include "kernels/distribution.h"
#include "kernels/sampling.h"
#include "kernels/texture.h"
#include "wavemmlt/scene_desc.h"

namespace wmlt {

struct MeshLight {
    const TriangleMesh* mesh = nullptr;
    Distribution1D triangles;
    double area = 0;  // the emitting area
    // Textured: the texture, each triangle's grid in `grids` (-1: one cell, uniform in it)
    // and area, and T's mean luminance over the surface (the light's power factor).
    const TextureDesc* texture = nullptr;
    std::vector<int32_t> gridOf;
    std::vector<Distribution2D> grids;
    std::vector<float> areas;
    float meanLuminance = 1;
};

// Builds the light of mesh m (texture: nullptr for a constant radiance).
MeshLight buildMeshLight(const TriangleMesh& m, const TextureDesc* texture);

// The (u, v) at weights (b1, b2) of triangle t's second and third corners.
inline void meshUvAt(const TriangleMesh& m, int t, float b1, float b2, float& u, float& v) {
    const uint32_t* tri = &m.indices[size_t(t) * 3];
    const float* a = &m.uvs[2 * size_t(tri[0])];
    const float* b = &m.uvs[2 * size_t(tri[1])];
    const float* c = &m.uvs[2 * size_t(tri[2])];
    const float b0 = 1.0f - b1 - b2;
    u = a[0] * b0 + b[0] * b1 + c[0] * b2;
    v = a[1] * b0 + b[1] * b1 + c[1] * b2;
}

// The point of triangle t at (a, b) of sampleUniformTriangle's square, its winding normal
// cross(p1 - p0, p2 - p0) (Embree's Ng, the side a mesh light emits on) and the weights
// (b1, b2) of its second and third corners.
inline void meshTrianglePoint(const TriangleMesh& m, int t, float a, float b, Vec3& p, Vec3& n, float& b1, float& b2) {
    const uint32_t* tri = &m.indices[size_t(t) * 3];
    const Vec3 p0 = m.positions[tri[0]], p1 = m.positions[tri[1]], p2 = m.positions[tri[2]];
    float b0;
    sampleUniformTriangle(a, b, b0, b1);
    b2 = 1.0f - b0 - b1;
    p = p0 * b0 + p1 * b1 + p2 * b2;
    n = normalize(cross(p1 - p0, p2 - p0));
}

// A constant mesh light's point from (u1, u2): a triangle in proportion to its area (u1
// picks it and is reused within it), a uniform point in it (area density 1 / area).
inline void sampleMeshPoint(const MeshLight& m, float u1, float u2, Vec3& p, Vec3& n) {
    float ur = 0, b1, b2;
    const int t = m.triangles.sampleDiscrete(u1, nullptr, &ur);
    meshTrianglePoint(*m.mesh, t, ur, u2, p, n, b1, b2);
}

// A textured mesh light at triangle t, weights (b1, b2) of its second and third corners
// (Embree's hit u, v), point p: T there and the area density with which
// sampleTexturedMeshPoint makes the point (the warp inverted: a = (b1 + b2)^2,
// b = b1 / (b1 + b2)).
inline void texturedEmitterAt(const MeshLight& m, int t, float b1, float b2, Vec3 p, Vec3& tex, float& pdfA) {
    float u, v;
    meshUvAt(*m.mesh, t, b1, b2, u, v);
    tex = evalTexture(*m.texture, u, v, p);
    const float su = b1 + b2;
    const int g = m.gridOf[size_t(t)];
    const float pdf2 = g < 0 ? 1.0f : m.grids[size_t(g)].pdf(su * su, su > 0 ? b1 / su : 0.0f);
    pdfA = m.triangles.discretePmf(t) * pdf2 / m.areas[size_t(t)];
}

// A point of a textured mesh light from (u1, u2): position, winding normal, T and pdfA.
inline void sampleTexturedMeshPoint(const MeshLight& m, float u1, float u2, Vec3& p, Vec3& n, Vec3& tex, float& pdfA) {
    float pmf, ur = 0;
    const int t = m.triangles.sampleDiscrete(u1, &pmf, &ur);
    float a = ur, b = u2, pdf2 = 1;
    const int g = m.gridOf[size_t(t)];
    if (g >= 0) m.grids[size_t(g)].sampleContinuous(ur, u2, a, b, &pdf2);
    float b1, b2;
    meshTrianglePoint(*m.mesh, t, a, b, p, n, b1, b2);
    float u, v;
    meshUvAt(*m.mesh, t, b1, b2, u, v);
    tex = evalTexture(*m.texture, u, v, p);
    pdfA = pmf * pdf2 / m.areas[size_t(t)];
}

}  // namespace wmlt
