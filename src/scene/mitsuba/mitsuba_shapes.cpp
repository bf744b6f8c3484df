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

}  // namespace wmlt::mitsuba
