// Vertex normals for smooth shading, shared by the PLY and serialized readers (Mitsuba
// computes vertex normals for a mesh without them unless face_normals is set).
#pragma once
#include <vector>

#include "wavemmlt/scene_desc.h"

namespace wmlt {

// Sets mesh.normals to one per vertex: the file's (3 floats per vertex, normalised) where
// given and of usable length, else the area-weighted sum of the adjacent faces' normals.
// `fileNormals` empty: every vertex gets the area-weighted one.
void smoothVertexNormals(TriangleMesh& mesh, const std::vector<float>& fileNormals);

}  // namespace wmlt
