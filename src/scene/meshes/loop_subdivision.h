// Loop subdivision (Loop 1987) as pbrt-v4's loopsubdiv shape makes it: `levels` rounds of
// splitting each triangle in four (old vertices (1 - n beta) v + beta sum of the one-ring,
// beta = 3/16 at valence 3 else 3 / 8n; new edge vertices 3/8 of the ends + 1/8 of the
// opposite corners; on a boundary 3/4 v + 1/8 of the two boundary neighbours and the edge's
// midpoint), then every vertex pushed to the limit surface (gamma = 1 / (n + 3 / 8 beta);
// 3/5 v + 1/5 of the boundary neighbours) with the limit normal cross(S, T) of the one-ring's
// tangents (pbrt's boundary weights).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "wavemmlt/math.h"

namespace wmlt {

// P and idx (3 per triangle) in, subdivided positions, triangles and normals out. Returns ""
// or the problem (an edge of more than two faces, faces of opposite winding across an edge,
// a vertex whose faces are not one fan).
std::string loopSubdivide(std::vector<Vec3>& P, std::vector<uint32_t>& idx, int levels, std::vector<Vec3>& N);

}  // namespace wmlt
