#include "scene/meshes/vertex_normals.h"

#include <cmath>

namespace wmlt {

void smoothVertexNormals(TriangleMesh& out, const std::vector<float>& nrm) {
    const size_t nVertices = out.positions.size();
    const bool haveNormals = !nrm.empty();
    out.normals.assign(nVertices, Vec3(0.0f));
    bool missing = !haveNormals;
    for (size_t i = 0; i < nVertices && haveNormals; ++i) {
        const Vec3 n(nrm[3 * i], nrm[3 * i + 1], nrm[3 * i + 2]);
        const float l = length(n);
        if (l > 0 && std::isfinite(l)) out.normals[i] = n / l;
        else missing = true;
    }
    if (!missing) return;
    std::vector<Vec3> acc(nVertices, Vec3(0.0f));
    for (size_t t = 0; t + 2 < out.indices.size(); t += 3) {
        const Vec3 a = out.positions[out.indices[t]], b = out.positions[out.indices[t + 1]], c = out.positions[out.indices[t + 2]];
        const Vec3 n = cross(b - a, c - a);  // length = 2 * area
        for (int k = 0; k < 3; ++k) acc[out.indices[t + size_t(k)]] += n;
    }
    for (size_t i = 0; i < nVertices; ++i) {
        if (!isBlack(out.normals[i])) continue;
        const float l = length(acc[i]);
        out.normals[i] = l > 0 && std::isfinite(l) ? acc[i] / l : Vec3(0, 1, 0);  // (a vertex of no area is never hit)
    }
}

}  // namespace wmlt
