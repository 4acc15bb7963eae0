#pragma once
// Thin parts: a closed part narrower than the sampling spacing (a table's legs, a rod, a
// handle modelled as a box) gets samples on one face only, since a sample blocks every point
// within h, across the part too. Drawn as surfels, those face one way: seen from the side the
// part shows gaps, and the mesh occluders behind them show as black. The spacing is held to a
// fraction of the thinnest part's thickness so that every face of it carries samples.
#include <cstddef>
#include <limits>

#include "mesh/triangle_mesh.h"

namespace pbdsplat::surface {

// A part counts when it holds at least this share of the surface's area: a screw on a machine
// does not make the whole machine fine.
inline constexpr float k_thin_part_area_share = 0.01f;
// Spacing over mean thickness: about three samples across each face of a square rod, and a row
// down a plate's edge (4 V / A is twice a plate's thickness): at half of it a plate's edge was
// ragged and its holes 0.51 %, 0.05 % at this.
inline constexpr float k_spacing_over_thickness = 0.35f;

// 4 V / A of a closed part (its volume over its area): the diameter of a rod, the side of a
// square post, a little over the thickness of a plate.
float mean_thickness(double volume, double area);

// The largest spacing that puts samples on every face of each closed part of `mesh` (connected
// through shared vertices, every edge shared by two of its triangles) that holds at least
// k_thin_part_area_share of the area: k_spacing_over_thickness times the thinnest such part's
// mean thickness. Infinity where no part counts (open surfaces have no thickness to keep) or
// none would ask for less than `below`: only parts that would are tested for being closed, so a
// model whose parts are all thick beside its edges (nearly every scan) costs one pass.
float spacing_for_thin_parts(const mesh::TriangleMesh& mesh, float below = std::numeric_limits<float>::infinity());

} // namespace pbdsplat::surface
