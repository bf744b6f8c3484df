#include "scene/mesh_light.h"

#include <algorithm>
#include <cmath>

namespace wmlt {

namespace {

constexpr int kMaxGrid = 64;  // cells along each side of a triangle's square, at most
// Meshes of more triangles than this: one cell each (the triangles are the grid; no
// per-triangle tables for millions of small triangles).
constexpr size_t kGridTriangles = 4096;
constexpr int kCellPoints = 3;  // a cell's mean from kCellPoints^2 points
constexpr float kFloor = 0.1f;  // defensive: no cell below 1/10 of the mean (a sliver its points missed)

// Texels (or checker squares) triangle t's (u, v) covers, after the texture's to_uv.
double texelsCovered(const TriangleMesh& m, size_t t, const TextureDesc& tex) {
    float u[3], v[3];
    for (int c = 0; c < 3; ++c) {
        const uint32_t i = m.indices[3 * t + size_t(c)];
        u[c] = m.uvs[2 * size_t(i)];
        v[c] = m.uvs[2 * size_t(i) + 1];
    }
    const double uvArea = 0.5 * std::fabs(double(u[1] - u[0]) * (v[2] - v[0]) - double(u[2] - u[0]) * (v[1] - v[0]));
    const float* a = tex.uvTransform;
    const double det = std::fabs(double(a[0]) * a[4] - double(a[1]) * a[3]);
    const double perUnit =
        tex.image.width > 0 ? double(tex.image.width) * tex.image.height : 1024.0;  // checkers (2 x 2 squares a unit): 32 x 32 cells a unit
    const double texels = uvArea * det * perUnit;
    return std::isfinite(texels) ? texels : 0.0;
}

}  // namespace

MeshLight buildMeshLight(const TriangleMesh& m, const TextureDesc* texture) {
    MeshLight ml;
    ml.mesh = &m;
    const size_t nt = m.indices.size() / 3;
    ml.areas.resize(nt);
    for (size_t t = 0; t < nt; ++t) {
        const Vec3 p0 = m.positions[m.indices[3 * t]], p1 = m.positions[m.indices[3 * t + 1]], p2 = m.positions[m.indices[3 * t + 2]];
        ml.areas[t] = 0.5f * length(cross(p1 - p0, p2 - p0));
        if (!std::isfinite(ml.areas[t])) ml.areas[t] = 0;
        ml.area += ml.areas[t];
    }
    if (!texture) {
        ml.triangles.build(ml.areas.data(), nt);
        ml.areas.clear();
        return ml;
    }
    ml.texture = texture;
    // Each triangle's cells: the mean luminance of T over kCellPoints^2 points of the cell,
    // mapped through the warp to the triangle.
    std::vector<int> side(nt);
    std::vector<size_t> first(nt + 1, 0);
    for (size_t t = 0; t < nt; ++t) {
        const double n = std::ceil(std::sqrt(texelsCovered(m, t, *texture)));
        side[t] = nt > kGridTriangles ? 1 : int(std::clamp(n, 1.0, double(kMaxGrid)));
        first[t + 1] = first[t] + size_t(side[t]) * size_t(side[t]);
    }
    std::vector<float> cell(first[nt]);
    double weighted = 0;
    for (size_t t = 0; t < nt; ++t) {
        const int n = side[t];
        double sum = 0;
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                double lum = 0;
                for (int j = 0; j < kCellPoints; ++j)
                    for (int i = 0; i < kCellPoints; ++i) {
                        const float a = (float(x) + (float(i) + 0.5f) / kCellPoints) / float(n);
                        const float b = (float(y) + (float(j) + 0.5f) / kCellPoints) / float(n);
                        Vec3 p, n;
                        float b1, b2, u, v;
                        meshTrianglePoint(m, int(t), a, b, p, n, b1, b2);
                        meshUvAt(m, int(t), b1, b2, u, v);
                        const float l = luminance(evalTexture(*texture, u, v, p));
                        lum += std::isfinite(l) && l > 0 ? l : 0.0;
                    }
                cell[first[t] + size_t(y * n + x)] = float(lum / (kCellPoints * kCellPoints));
                sum += lum / (kCellPoints * kCellPoints);
            }
        weighted += ml.areas[t] * sum / (double(n) * n);
    }
    const double mean = ml.area > 0 ? weighted / ml.area : 0.0;
    const float floor = float(std::max(mean, 1e-30)) * kFloor;
    std::vector<float> triangleWeight(nt);
    double total = 0;
    for (size_t t = 0; t < nt; ++t) {
        const int n = side[t];
        double sum = 0;
        for (size_t c = first[t]; c < first[t + 1]; ++c) {
            cell[c] = std::max(cell[c], floor);
            sum += cell[c];
        }
        triangleWeight[t] = float(ml.areas[t] * sum / (double(n) * n));
        total += triangleWeight[t];
        if (n > 1) {
            ml.gridOf.push_back(int32_t(ml.grids.size()));
            ml.grids.emplace_back();
            ml.grids.back().build(&cell[first[t]], n, n);
        } else {
            ml.gridOf.push_back(-1);
        }
    }
    ml.triangles.build(triangleWeight.data(), nt);
    ml.meanLuminance = ml.area > 0 ? float(total / ml.area) : 0.0f;
    return ml;
}

}  // namespace wmlt
