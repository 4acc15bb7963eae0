#pragma once
// Where a triangle made by a topology change came from: its parent (the triangle it replaced
// part of) and its corners in the parent's barycentric coordinates. Anything attached to the
// surface by barycentric coordinates (boundary particles) moves to the children with it, so
// nothing jumps on screen when a triangle is re-triangulated.
#include <array>
#include <cstdint>

#include "core/math.h"

namespace pbdsplat::mesh {

struct TriangleSplit {
    uint32_t triangle = 0;  // index of the child in the new triangle list
    uint32_t parent = 0;    // index of the parent in the old list (the first child reuses it)
    std::array<Vec3f, 3> corners;  // child corner k = sum_c corners[k][c] * parent corner c
};

} // namespace pbdsplat::mesh
