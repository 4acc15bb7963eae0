#pragma once
// Procedural meshes, so tests, benchmarks and the default scene need no file. All are welded,
// manifold and outward-oriented; all but the grid sheet are closed.
#include <cstdint>
#include <vector>

#include "mesh/triangle_mesh.h"

namespace pbdsplat::mesh {

// Unit-radius icosphere: an icosahedron with every triangle split in four `level` times and
// the vertices pushed onto the sphere. V = 10*4^level + 2, F = 20*4^level.
TriangleMesh icosphere(uint32_t level, float radius = 1.0f);

// Latitude-longitude sphere: `rings` >= 2 bands from pole to pole, `segments` >= 3 around.
TriangleMesh uv_sphere(uint32_t rings, uint32_t segments, float radius = 1.0f);

// Torus around the y axis: ring radius `major`, tube radius `minor`.
TriangleMesh torus(uint32_t segments, uint32_t sides, float major = 1.0f, float minor = 0.35f);

// Axis-aligned box centred at the origin, each face split into `divisions`^2 quads.
TriangleMesh box(const Vec3f& size, uint32_t divisions);

// Capsule along y: a cylinder of `length` capped by hemispheres of `radius`.
TriangleMesh capsule(float radius, float length, uint32_t rings, uint32_t segments);

// A four-legged animal-like solid made of cubes: a block body on four thin square legs at its
// corners, a head sticking out in front; 1 tall, 8/7 long, 3/7 wide, legs 1/7 thick and 4/7 tall,
// centred on the origin; `divisions` cubes across a leg. Thin parts carrying a front-heavy body:
// the test of whether a solid stands under its own weight.
TriangleMesh quadruped(uint32_t divisions);

// A table of five closed parts that share no vertex, as furniture is modelled: a top 1.2 x 0.05
// x 0.8 on four legs 0.05 square and 0.7 tall, inset 0.05 from its corners, each leg a
// hair (a fiftieth of a cell) under the top; centred on the origin, its faces in square cells
// of 0.05 / `divisions`. The case of a model whose thin parts are held to the rest by welds.
TriangleMesh table(uint32_t divisions);

// Open square sheet in the xz plane, `n` x `n` quads, side `size`, centred at the origin.
TriangleMesh grid_sheet(uint32_t n, float size = 1.0f);

// `count` points spread evenly over a sphere (Fibonacci lattice), e.g. benchmark splat clouds.
std::vector<Vec3f> fibonacci_sphere(uint32_t count, float radius = 1.0f);

} // namespace pbdsplat::mesh
