#pragma once
// Vertex and triangle order for cache locality: neighbours in space become neighbours in
// memory, so a constraint sweep touches few cache lines. Any order gives the same surface.
#include <cstdint>
#include <vector>

#include "mesh/triangle_mesh.h"

namespace pbdsplat::mesh {

// Sorts vertices along a Morton (Z-order) curve of their positions and triangles by their
// first vertex; returns new_index_of_old for callers that keep per-vertex data of their own.
std::vector<uint32_t> reorder_for_locality(TriangleMesh& mesh);

} // namespace pbdsplat::mesh
