#pragma once
// Triangles of one polygon face (an OBJ 'f' line with more than three corners, a PLY face):
// ear clipping in the polygon's best-fit plane, so a concave outline (an L, a C, a ring joined
// by a bridge edge) keeps its notches instead of being filled as a fan would fill it.
// And the surface spanning a closed loop in space (a cut face's outline) with the least area.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "core/math.h"

namespace pbdsplat::mesh {

// Corner triples (indices into `corners`), counter-clockwise like the outline. A degenerate
// outline (collinear, repeated corners) that no ear can be clipped from, or one of more than
// 4,096 corners, is split as a fan, and repair drops what is degenerate.
std::vector<std::array<uint32_t, 3>> triangulate_polygon(std::span<const Vec3f> corners);

// Corner triples wound like the loop, spanning it with the least total area (dynamic programming
// over its chords, cubic in the corners). A planar outline gets triangles inside it only (one
// crossing the outline would add area); a loop that runs over two planes (a cut across the face
// an earlier cut left, whose outline goes down one face and back along the other) folds along
// their common chord instead of spanning the wedge between them. More than
// k_max_least_area_corners corners: triangulate_polygon's.
inline constexpr size_t k_max_least_area_corners = 400;
std::vector<std::array<uint32_t, 3>> triangulate_least_area(std::span<const Vec3f> corners);

} // namespace pbdsplat::mesh
