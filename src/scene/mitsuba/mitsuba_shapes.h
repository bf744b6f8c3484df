// Mitsuba's built-in shapes as triangle meshes in their object space (Mitsuba 3's
// definitions): rectangle [-1, 1]^2 at z = 0 with normal +z, cube [-1, 1]^3 with outward
// faces, disk of radius 1 at z = 0 (a polygon). uv as Mitsuba defines them (v = 0 at the
// bottom of the shape's parameter square).
#pragma once
#include "scene/mitsuba/mitsuba_xml.h"

namespace wmlt::mitsuba {

TriangleMesh rectangleMesh();
TriangleMesh cubeMesh();
TriangleMesh diskMesh(int segments);

using wmlt::transformMesh;

}  // namespace wmlt::mitsuba
