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
// crossing the outline would add area). More than k_max_least_area_corners corners:
// triangulate_polygon's.
inline constexpr size_t k_max_least_area_corners = 400;
std::vector<std::array<uint32_t, 3>> triangulate_least_area(std::span<const Vec3f> corners);

// The face of a loop a cut made across an older face: `older[k]` says corner k lay on the older
// face's loop. Each run of older corners, closed by the chord between the new corners at its
// ends, spans the older face's part; the new corners, those chords in place of the runs, span the
// cut's part; each part with the least area. The face folds along the chords, where the cut
// crossed the older face. The least area over the whole loop does not: where the piece is the
// wedge between the two planes, a surface cutting across the wedge has less area than its two
// faces, and it would leave the wedge's shell open to the eye and to contact. No older corner,
// or no new one: triangulate_least_area's. `parts`, when given, gets each triangle's part: 0 the
// cut's, k the k-th run's (the planes the face folds between).
std::vector<std::array<uint32_t, 3>> triangulate_across_older(std::span<const Vec3f> corners, std::span<const uint8_t> older,
                                                              std::vector<uint8_t>* parts = nullptr);

} // namespace pbdsplat::mesh
