#pragma once
// How the surface's normal turns across each splat. The paper lights a splat with one normal,
// so on a curved or crumpled body every disc is a flat facet whose shade jumps at its border
// (sequins; a disc that catches a highlight shows it whole). Each record instead carries the
// derivative of the surface's normal, and the splat paths turn the normal at each carrier corner
// by it (a linear normal field per splat, as in Phong splatting): the shade then runs on across
// neighbouring discs as it does across the mesh raster's triangles. The field is the one that
// raster interpolates: vertex normals, linear over each triangle.
//
// The derivative is a symmetric 3x3 S in world axes (a step p in the tangent plane turns the
// normal by S p), built once per triangle (or vertex). S n = 0, so a record keeps three of its
// entries, the 2x2 block off the normal's largest axis, and the shader rebuilds the rest from its
// normal: a splat costs a few copies and no tangent frame, and the record stays 32 bytes.
#include <array>
#include <span>
#include <vector>

#include "core/math.h"
#include "mesh/triangle_mesh.h"
#include "splat/gaussian_record.h"

namespace pbdsplat::splat {

using SymmetricCurvature = std::array<float, 6>;  // xx, xy, xz, yy, yz, zz

class NormalField {
public:
    // Per triangle: the derivative of its interpolated vertex normals, restricted to its plane
    // and symmetrised (zero on a sliver). With `vertices`, also the area-weighted mean at each
    // vertex. Every entry is clamped to `limit` per world unit (curvature_limit), so a crumple's
    // fold cannot turn a disc's normal past tangent within it.
    void update(std::span<const Vec4f> x, std::span<const Vec3f> vertex_normals, std::span<const mesh::Triangle> triangles,
                bool vertices, float limit);
    const SymmetricCurvature& triangle(uint32_t t) const { return triangle_[t]; }
    const SymmetricCurvature& vertex(uint32_t v) const { return vertex_[v]; }
    bool has_vertices() const { return !vertex_.empty(); }

private:
    std::vector<SymmetricCurvature> triangle_, vertex_;
    std::vector<float> weight_;
};

Mat3f to_matrix(const SymmetricCurvature& s);
SymmetricCurvature to_symmetric(const Mat3f& m, float limit);
// Writes S into a record whose normal is `normal` (the unit normal it encodes), and back: the
// full S the shader rebuilds from the record's decoded normal.
void set_curvature(const SymmetricCurvature& s, const Vec3f& normal, GaussianRecord& r);
// The three stored entries only, into r.curvature_half[0..2]; returns the left-out axis, which
// the caller packs into entry 3 with the thinning place (pack_curvature_w): the mapping of many
// samples writes that entry once instead of decoding and re-encoding it.
int set_curvature_entries(const SymmetricCurvature& s, const Vec3f& normal, GaussianRecord& r);
Mat3f decode_curvature(const GaussianRecord& r);
// The limit for splats of std dev `scale`: the normal turns at most 45 degrees per std dev.
inline float curvature_limit(float scale) { return scale > 0.0f ? 1.0f / scale : 0.0f; }

} // namespace pbdsplat::splat
