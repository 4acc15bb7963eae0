#pragma once
// How the surface's normal turns across each splat. The paper lights a splat with one normal,
// so on a curved or crumpled body every disc is a flat facet whose shade jumps at its border
// (sequins; a disc that catches a highlight shows it whole). Each record instead carries the
// derivative of the surface's normal, and the splat paths turn the normal at each carrier corner
// by it (a linear normal field per splat, as in Phong splatting): the shade then runs on across
// neighbouring discs as it does across the mesh raster's triangles. The field is the one that
// raster interpolates: vertex normals, linear over each triangle.
//
// It is stored as a symmetric 3x3 S in world axes (six halves), so that a step p in the tangent
// plane turns the normal by S p: the work is per triangle (or per vertex), a splat only copies
// its triangle's, and the GPU needs no tangent frame.
#include <array>
#include <span>
#include <vector>

#include "core/math.h"
#include "mesh/triangle_mesh.h"
#include "splat/gaussian_record.h"

namespace pbdsplat::splat {

using PackedCurvature = std::array<uint16_t, 6>;  // xx, xy, xz, yy, yz, zz as IEEE halves

class NormalField {
public:
    // Per triangle: the derivative of its interpolated vertex normals, restricted to its plane
    // and symmetrised (zero on a sliver). With `vertices`, also the area-weighted mean at each
    // vertex. Every entry is clamped to `limit` per world unit (curvature_limit), so a crumple's
    // fold cannot turn a disc's normal past tangent within it.
    void update(std::span<const Vec4f> x, std::span<const Vec3f> vertex_normals, std::span<const mesh::Triangle> triangles,
                bool vertices, float limit);
    const PackedCurvature& triangle(uint32_t t) const { return triangle_[t]; }
    const PackedCurvature& vertex(uint32_t v) const { return vertex_[v]; }
    bool has_vertices() const { return !vertex_.empty(); }

private:
    std::vector<PackedCurvature> triangle_, vertex_;
    std::vector<std::array<float, 6>> vertex_sum_;
    std::vector<float> weight_;
};

// The symmetric 3x3 as a record stores it, and back (tests and tools).
PackedCurvature pack_curvature(const Mat3f& s, float limit);
Mat3f decode_curvature(const GaussianRecord& r);
inline void set_curvature(const PackedCurvature& c, GaussianRecord& r) {
    for (int k = 0; k < 6; ++k) r.curvature_half[k] = c[size_t(k)];
}
// The limit for splats of std dev `scale`: the normal turns at most 45 degrees per std dev.
inline float curvature_limit(float scale) { return scale > 0.0f ? 1.0f / scale : 0.0f; }

} // namespace pbdsplat::splat
