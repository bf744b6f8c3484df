#include "scene/meshes/loop_subdivision.h"

#include <cmath>
#include <map>
#include <utility>

namespace wmlt {

namespace {

// Loop's weights: beta for the old vertices' update, gamma for the limit position.
double beta(int valence) { return valence == 3 ? 3.0 / 16.0 : 3.0 / (8.0 * valence); }
double gamma(int valence) { return 1.0 / (valence + 3.0 / (8.0 * beta(valence))); }

// Each vertex's neighbourhood: the rotation about it (in a face where prev(v) = p,
// next(v) = n: around[v][p] = n) from which its one-ring is walked in pbrt's order.
struct Rings {
    std::vector<std::map<uint32_t, uint32_t>> around, back;  // p -> n and n -> p
    std::vector<std::vector<uint32_t>> ring;                 // ordered one-ring
    std::vector<uint8_t> boundary;
};

// Returns "" or the problem (a non-manifold vertex or edge).
std::string rings(size_t nv, const std::vector<uint32_t>& idx, Rings& r) {
    r.around.assign(nv, {});
    r.back.assign(nv, {});
    r.ring.assign(nv, {});
    r.boundary.assign(nv, 0);
    for (size_t t = 0; t + 2 < idx.size(); t += 3)
        for (int i = 0; i < 3; ++i) {
            const uint32_t v = idx[t + size_t(i)], n = idx[t + size_t((i + 1) % 3)], p = idx[t + size_t((i + 2) % 3)];
            if (!r.around[v].emplace(p, n).second || !r.back[v].emplace(n, p).second)
                return "an edge shared by more than two faces, or faces of opposite winding (vertex " + std::to_string(v) + ")";
        }
    for (size_t v = 0; v < nv; ++v) {
        const auto& a = r.around[v];
        if (a.empty()) continue;
        std::vector<uint32_t>& ring = r.ring[v];
        uint32_t start = a.begin()->first;
        for (const auto& [p, n] : a)  // a boundary vertex: start at the neighbour no face precedes
            if (!a.count(n)) {
                r.boundary[v] = 1;
                start = n;
            }
        if (!r.boundary[v]) {  // interior: r_{j+1} = around[r_j], back to the start
            uint32_t x = start;
            do {
                ring.push_back(x);
                x = a.at(x);
            } while (x != start && ring.size() <= a.size());
            if (ring.size() != a.size()) return "a vertex whose faces do not form one fan (vertex " + std::to_string(v) + ")";
        } else {  // boundary: from that neighbour backwards, r_{j+1} = back[r_j]
            const auto& b = r.back[v];
            uint32_t x = start;
            ring.push_back(x);
            while (b.count(x) && ring.size() <= a.size() + 1) {
                x = b.at(x);
                ring.push_back(x);
            }
            if (ring.size() != a.size() + 1) return "a vertex whose faces do not form one fan (vertex " + std::to_string(v) + ")";
        }
    }
    return "";
}

// Each vertex moved to a weighted mean of itself and its one-ring: on a boundary
// centre v + side (b0 + b1) (its two boundary neighbours); inside (1 - n w(n)) v + w(n) sum.
template <typename Weight>
std::vector<Vec3> oneRingAverages(const std::vector<Vec3>& pos, const Rings& r, float centre, float side, Weight w) {
    std::vector<Vec3> out(pos.size());
    for (size_t v = 0; v < pos.size(); ++v) {
        const std::vector<uint32_t>& ring = r.ring[v];
        if (ring.empty()) {
            out[v] = pos[v];
        } else if (r.boundary[v]) {
            out[v] = pos[v] * centre + (pos[ring.front()] + pos[ring.back()]) * side;
        } else {
            const int n = int(ring.size());
            const double b = w(n);
            Vec3 sum(0.0f);
            for (uint32_t x : ring) sum = sum + pos[x];
            out[v] = pos[v] * float(1 - n * b) + sum * float(b);
        }
    }
    return out;
}

}  // namespace

std::string loopSubdivide(std::vector<Vec3>& P, std::vector<uint32_t>& idx, int levels, std::vector<Vec3>& N) {
    std::vector<Vec3> pos = P;
    Rings r;
    for (int level = 0; level < levels; ++level) {
        const std::string why = rings(pos.size(), idx, r);
        if (!why.empty()) return why;
        std::vector<Vec3> next = oneRingAverages(pos, r, 0.75f, 0.125f, beta);  // the old vertices
        // one new vertex per edge: 3/8 its ends + 1/8 the opposite corners; 1/2 on a boundary
        std::map<std::pair<uint32_t, uint32_t>, uint32_t> edgeVertex;
        auto edge = [&](uint32_t a, uint32_t b) {
            const auto key = std::make_pair(std::min(a, b), std::max(a, b));
            auto it = edgeVertex.find(key);
            if (it != edgeVertex.end()) return it->second;
            const auto fa = r.around[a].find(b), fb = r.around[b].find(a);  // faces with prev(a) = b, prev(b) = a
            Vec3 q;
            if (fa == r.around[a].end() || fb == r.around[b].end()) q = (pos[a] + pos[b]) * 0.5f;
            else q = (pos[a] + pos[b]) * 0.375f + (pos[fa->second] + pos[fb->second]) * 0.125f;
            next.push_back(q);
            edgeVertex.emplace(key, uint32_t(next.size() - 1));
            return uint32_t(next.size() - 1);
        };
        std::vector<uint32_t> out;
        out.reserve(idx.size() * 4);
        for (size_t t = 0; t + 2 < idx.size(); t += 3) {
            const uint32_t a = idx[t], b = idx[t + 1], c = idx[t + 2];
            const uint32_t ab = edge(a, b), bc = edge(b, c), ca = edge(c, a);
            out.insert(out.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
        }
        pos = std::move(next);
        idx = std::move(out);
    }
    // the limit surface: positions, then the normals from tangents over the limit one-ring
    const std::string why = rings(pos.size(), idx, r);
    if (!why.empty()) return why;
    const std::vector<Vec3> limit = oneRingAverages(pos, r, 0.6f, 0.2f, gamma);
    N.assign(pos.size(), Vec3(0.0f));
    for (size_t v = 0; v < pos.size(); ++v) {
        const std::vector<uint32_t>& ring = r.ring[v];
        const int n = int(ring.size());
        if (n == 0) continue;
        Vec3 S(0.0f), T(0.0f);
        const Vec3 p = limit[v];
        auto at = [&](int k) { return limit[ring[size_t(k)]]; };
        if (!r.boundary[v]) {
            for (int j = 0; j < n; ++j) {
                S = S + at(j) * float(std::cos(2 * M_PI * j / n));
                T = T + at(j) * float(std::sin(2 * M_PI * j / n));
            }
        } else {
            S = at(n - 1) - at(0);
            if (n == 2) T = at(0) + at(1) - p * 2.0f;
            else if (n == 3) T = at(1) - p;
            else if (n == 4) T = at(0) * -1.0f + at(1) * 2.0f + at(2) * 2.0f - at(3) - p * 2.0f;
            else {
                const double th = M_PI / (n - 1);
                T = (at(0) + at(n - 1)) * float(std::sin(th));
                for (int k = 1; k < n - 1; ++k) T = T + at(k) * float((2 * std::cos(th) - 2) * std::sin(k * th));
                T = -T;
            }
        }
        const Vec3 c = cross(S, T);
        const float l = length(c);
        N[v] = l > 0 && std::isfinite(l) ? c / l : Vec3(0, 0, 1);
    }
    P = std::move(limit);
    return "";
}

}  // namespace wmlt
