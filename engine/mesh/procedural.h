#pragma once
// Procedural meshes, so tests and the default scene need no file.
#include <cstdint>

#include "mesh/triangle_mesh.h"

namespace pbdsplat::mesh {

// Unit-radius icosphere: an icosahedron with every triangle split in four `level` times and
// the vertices pushed onto the sphere. V = 10*4^level + 2, F = 20*4^level; closed and outward.
TriangleMesh icosphere(uint32_t level, float radius = 1.0f);

} // namespace pbdsplat::mesh

namespace pbdsplat::mesh {
// `count` points spread evenly over a sphere (Fibonacci lattice), e.g. benchmark splat clouds.
std::vector<Vec3f> fibonacci_sphere(uint32_t count, float radius = 1.0f);
} // namespace pbdsplat::mesh
