#include "scene/mitsuba/mitsuba_shapes.h"

#include <cmath>

namespace wmlt::mitsuba {

TriangleMesh rectangleMesh() {
    TriangleMesh m;
    // Wound counter-clockwise seen from +z: cross(p1 - p0, p2 - p0) = +z (the emitting side),
    // in the two-triangle layout Scene's rectangle lights read.
    m.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
    m.uvs = {0, 0, 1, 0, 1, 1, 0, 1};
    m.indices = {0, 1, 2, 0, 2, 3};
    return m;
}

TriangleMesh cubeMesh() {
    TriangleMesh m;
    for (int axis = 0; axis < 3; ++axis)
        for (float sign : {-1.0f, 1.0f}) {
            const int a = (axis + 1) % 3, b = (axis + 2) % 3;  // (a, b, axis) right-handed
            const uint32_t base = uint32_t(m.positions.size());
            const float uv[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
            for (const auto& c : uv) {
                Vec3 p;
                p[axis] = sign;
                p[a] = c[0];
                p[b] = c[1];
                m.positions.push_back(p);
                m.uvs.push_back(0.5f * (c[0] + 1));
                m.uvs.push_back(0.5f * (c[1] + 1));
            }
            // cross(e_a, e_b) = +e_axis: counter-clockwise seen from outside on the + face.
            if (sign > 0) m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
            else m.indices.insert(m.indices.end(), {base, base + 2, base + 1, base, base + 3, base + 2});
        }
    return m;
}

TriangleMesh diskMesh(int n) {
    TriangleMesh m;
    m.positions.push_back({0, 0, 0});
    m.uvs.insert(m.uvs.end(), {0.5f, 0.5f});
    for (int i = 0; i < n; ++i) {
        const double phi = 2 * M_PI * i / n;
        m.positions.push_back({float(std::cos(phi)), float(std::sin(phi)), 0});
        m.uvs.insert(m.uvs.end(), {0.5f + 0.5f * float(std::cos(phi)), 0.5f + 0.5f * float(std::sin(phi))});
        m.indices.insert(m.indices.end(), {0u, uint32_t(1 + i), uint32_t(1 + (i + 1) % n)});
    }
    return m;
}

void transformMesh(TriangleMesh& mesh, const Matrix& M, bool flip) {
    const Matrix inv = M.inverse();
    for (Vec3& p : mesh.positions) p = M.point(p);
    for (Vec3& n : mesh.normals) {
        Vec3 w(float(inv.m[0][0] * n.x + inv.m[1][0] * n.y + inv.m[2][0] * n.z),
               float(inv.m[0][1] * n.x + inv.m[1][1] * n.y + inv.m[2][1] * n.z),
               float(inv.m[0][2] * n.x + inv.m[1][2] * n.y + inv.m[2][2] * n.z));
        const float l = length(w);
        n = l > 0 && std::isfinite(l) ? (flip ? -w : w) / l : Vec3(0, 0, 1);
    }
    if (flip)
        for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) std::swap(mesh.indices[t + 1], mesh.indices[t + 2]);
}

}  // namespace wmlt::mitsuba
