#pragma once
// Triangles of one polygon face (an OBJ 'f' line with more than three corners, a PLY face):
// ear clipping in the polygon's best-fit plane, so a concave outline (an L, a C, a ring joined
// by a bridge edge) keeps its notches instead of being filled as a fan would fill it.
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

} // namespace pbdsplat::mesh
