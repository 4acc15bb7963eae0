#pragma once
// One-to-four subdivision: every edge gets a midpoint (shared by its two triangles), every
// triangle four children. Flat by default, so a cube stays a cube; the icosphere projects its
// midpoints onto the sphere.
#include <cstdint>
#include <functional>

#include "mesh/triangle_mesh.h"

namespace pbdsplat::mesh {

// `midpoint(a, b)` gives the new vertex's position from the edge's two; colours are averaged,
// normals and texture coordinates dropped (the result's are derived again downstream).
void subdivide(TriangleMesh& mesh, const std::function<Vec3f(const Vec3f&, const Vec3f&)>& midpoint);
void subdivide_flat(TriangleMesh& mesh);

// Subdivides flat until the mesh has at least `min_vertices` vertices (or `max_levels` times);
// returns the levels applied. A model of a few vertices (an 8-vertex cube) has edges so long
// that the sampling spacing, and every splat, would span its faces.
uint32_t refine_to(TriangleMesh& mesh, size_t min_vertices, uint32_t max_levels = 6);

// Subdivides flat, part by part (parts share no vertex), each until its longest edge is at most
// `edge_over_size` of its own bounding diagonal, at most `max_levels` times, and all of them
// fewer times where the mesh would pass `max_triangles` (or its own count, if larger). A model of
// many parts, some low-poly (a table of 8-vertex boxes beside a fine figure), has parts whose
// every particle and splat spans a face, and whose corners' averaged normals light a box as a
// ball. Returns the most levels a part took.
uint32_t refine_coarse_parts(TriangleMesh& mesh, float edge_over_size, uint32_t max_levels, size_t max_triangles);

} // namespace pbdsplat::mesh
