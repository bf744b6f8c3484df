#include "scene/meshes/loop_subdivision.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace wmlt {

namespace {

// Loop's weights: beta for the old vertices' update, gamma for the limit position.
double beta(int valence) { return valence == 3 ? 3.0 / 16.0 : 3.0 / (8.0 * valence); }
double gamma(int valence) { return 1.0 / (valence + 3.0 / (8.0 * beta(valence))); }

// Each vertex's neighbourhood: the rotation about it (in a face where prev(v) = p,
// next(v) = n, a corner (p, n) of v) from which its one-ring is walked in pbrt's order.
// Flat arrays: v's corners are [start[v], start[v + 1]) of prevOf / nextOf, sorted by p; its
// ordered one-ring [ringStart[v], ringStart[v + 1]) of ringV.
struct Rings {
    std::vector<uint32_t> start, prevOf, nextOf;
    std::vector<uint32_t> ringStart, ringV;
    std::vector<uint8_t> boundary;
    // around(v, p) = n of v's corner with prev p; back(v, n) = p of the one with next n;
    // kNone when v has none (a vertex's valence is small: a linear search).
    static constexpr uint32_t kNone = ~0u;
    uint32_t around(uint32_t v, uint32_t p) const {
        for (uint32_t s = start[v]; s < start[v + 1]; ++s)
            if (prevOf[s] == p) return nextOf[s];
        return kNone;
    }
    uint32_t back(uint32_t v, uint32_t n) const {
        for (uint32_t s = start[v]; s < start[v + 1]; ++s)
            if (nextOf[s] == n) return prevOf[s];
        return kNone;
    }
    size_t ringSize(uint32_t v) const { return ringStart[v + 1] - ringStart[v]; }
    uint32_t ringAt(uint32_t v, size_t k) const { return ringV[ringStart[v] + k]; }
};

// Returns "" or the problem (a non-manifold vertex or edge).
std::string rings(size_t nv, const std::vector<uint32_t>& idx, Rings& r) {
    r.start.assign(nv + 1, 0);
    for (uint32_t v : idx) ++r.start[size_t(v) + 1];
    for (size_t v = 0; v < nv; ++v) r.start[v + 1] += r.start[v];
    r.prevOf.resize(idx.size());
    r.nextOf.resize(idx.size());
    std::vector<uint32_t> fill(r.start.begin(), r.start.end() - 1);
    for (size_t t = 0; t + 2 < idx.size(); t += 3)
        for (int i = 0; i < 3; ++i) {
            const uint32_t v = idx[t + size_t(i)];
            const uint32_t s = fill[v]++;
            r.nextOf[s] = idx[t + size_t((i + 1) % 3)];
            r.prevOf[s] = idx[t + size_t((i + 2) % 3)];
        }
    r.boundary.assign(nv, 0);
    r.ringStart.assign(nv + 1, 0);
    r.ringV.clear();
    r.ringV.reserve(idx.size() + nv);
    std::vector<std::pair<uint32_t, uint32_t>> corners;
    for (size_t v = 0; v < nv; ++v) {
        const uint32_t s0 = r.start[v], s1 = r.start[v + 1];
        corners.clear();
        for (uint32_t s = s0; s < s1; ++s) corners.emplace_back(r.prevOf[s], r.nextOf[s]);
        std::sort(corners.begin(), corners.end());
        for (size_t k = 0; k < corners.size(); ++k) {
            r.prevOf[s0 + k] = corners[k].first;
            r.nextOf[s0 + k] = corners[k].second;
            // a p (or an n) twice about v: an edge of more than two faces or opposite windings
            if (k > 0 && corners[k].first == corners[k - 1].first)
                return "an edge shared by more than two faces, or faces of opposite winding (vertex " + std::to_string(v) + ")";
        }
        for (uint32_t s = s0; s < s1; ++s)
            for (uint32_t q = s + 1; q < s1; ++q)
                if (r.nextOf[s] == r.nextOf[q])
                    return "an edge shared by more than two faces, or faces of opposite winding (vertex " + std::to_string(v) + ")";
        r.ringStart[v] = uint32_t(r.ringV.size());
        const size_t valence = s1 - s0;
        if (valence == 0) {
            r.ringStart[v + 1] = uint32_t(r.ringV.size());
            continue;
        }
        uint32_t startV = r.prevOf[s0];
        for (uint32_t s = s0; s < s1; ++s)  // a boundary vertex: start at the neighbour no corner precedes
            if (r.around(uint32_t(v), r.nextOf[s]) == Rings::kNone) {
                r.boundary[v] = 1;
                startV = r.nextOf[s];
            }
        if (!r.boundary[v]) {  // interior: r_{j+1} = around(r_j), back to the start
            uint32_t x = startV;
            size_t n = 0;
            do {
                r.ringV.push_back(x);
                ++n;
                x = r.around(uint32_t(v), x);
            } while (x != startV && n <= valence);
            if (n != valence) return "a vertex whose faces do not form one fan (vertex " + std::to_string(v) + ")";
        } else {  // boundary: from that neighbour backwards, r_{j+1} = back(r_j)
            uint32_t x = startV;
            r.ringV.push_back(x);
            size_t n = 1;
            while (n <= valence + 1) {
                x = r.back(uint32_t(v), x);
                if (x == Rings::kNone) break;
                r.ringV.push_back(x);
                ++n;
            }
            if (n != valence + 1) return "a vertex whose faces do not form one fan (vertex " + std::to_string(v) + ")";
        }
        r.ringStart[v + 1] = uint32_t(r.ringV.size());
    }
    return "";
}

// Each vertex moved to a weighted mean of itself and its one-ring: on a boundary
// centre v + side (b0 + b1) (its two boundary neighbours); inside (1 - n w(n)) v + w(n) sum.
template <typename Weight>
std::vector<Vec3> oneRingAverages(const std::vector<Vec3>& pos, const Rings& r, float centre, float side, Weight w) {
    std::vector<Vec3> out(pos.size());
    for (size_t v = 0; v < pos.size(); ++v) {
        const size_t n = r.ringSize(uint32_t(v));
        if (n == 0) {
            out[v] = pos[v];
        } else if (r.boundary[v]) {
            out[v] = pos[v] * centre + (pos[r.ringAt(uint32_t(v), 0)] + pos[r.ringAt(uint32_t(v), n - 1)]) * side;
        } else {
            const double b = w(int(n));
            Vec3 sum(0.0f);
            for (size_t k = 0; k < n; ++k) sum = sum + pos[r.ringAt(uint32_t(v), k)];
            out[v] = pos[v] * float(1 - int(n) * b) + sum * float(b);
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
        std::unordered_map<uint64_t, uint32_t> edgeVertex;
        edgeVertex.reserve(idx.size());
        auto edge = [&](uint32_t a, uint32_t b) {
            const uint64_t key = uint64_t(std::min(a, b)) << 32 | std::max(a, b);
            auto it = edgeVertex.find(key);
            if (it != edgeVertex.end()) return it->second;
            const uint32_t fa = r.around(a, b), fb = r.around(b, a);  // faces with prev(a) = b, prev(b) = a
            Vec3 q;
            if (fa == Rings::kNone || fb == Rings::kNone) q = (pos[a] + pos[b]) * 0.5f;
            else q = (pos[a] + pos[b]) * 0.375f + (pos[fa] + pos[fb]) * 0.125f;
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
        const int n = int(r.ringSize(uint32_t(v)));
        if (n == 0) continue;
        Vec3 S(0.0f), T(0.0f);
        const Vec3 p = limit[v];
        auto at = [&](int k) { return limit[r.ringAt(uint32_t(v), size_t(k))]; };
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
