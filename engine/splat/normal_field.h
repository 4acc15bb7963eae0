#pragma once
// How the surface's normal turns across each splat. The paper lights a splat with one normal,
// so on a curved or crumpled body every disc is a flat facet whose shade jumps at its border
// (sequins; a disc that catches a highlight shows it whole). Each record instead carries the
// derivative of the surface's normal in its tangent plane, and the splat paths turn the normal
// at each carrier corner by it (a linear normal field per splat, as in Phong splatting): the
// shade then runs on across neighbouring discs as it does across the mesh raster's triangles.
// The field is the one that raster interpolates: vertex normals, linear over each triangle.
#include <span>
#include <vector>

#include "core/math.h"
#include "mesh/triangle_mesh.h"
#include "splat/gaussian_record.h"

namespace pbdsplat::splat {

// The tangent frame the GPU builds from a splat's decoded normal (splat_tangent_frame in
// shaders/shared/splat_codec.glsl): the curvature is stored in it, so both must agree.
void tangent_frame(const Vec3f& n, Vec3f& t1, Vec3f& t2);

// dn/dx of the interpolated vertex normals over each triangle (3x3, per world unit; zero on a
// sliver), and optionally its area-weighted mean at each vertex.
class NormalField {
public:
    void update(std::span<const Vec4f> x, std::span<const Vec3f> vertex_normals, std::span<const mesh::Triangle> triangles,
                bool vertices);
    const Mat3f& triangle(uint32_t t) const { return triangle_[t]; }
    const Mat3f& vertex(uint32_t v) const { return vertex_[v]; }
    bool has_vertices() const { return !vertex_.empty(); }

private:
    std::vector<Mat3f> triangle_, vertex_;
    std::vector<float> weight_;
};

// Stores dn/dx seen in the tangent frame of r's own encoded normal (symmetrised: the part that
// turns the normal as a surface's shape operator does), each entry at most `limit` per world
// unit, so a crumple's fold cannot turn a disc's normal past tangent within it.
void encode_curvature(const Mat3f& dndx, float limit, GaussianRecord& r);
// The stored (xx, xy, yy).
Vec3f decode_curvature(const GaussianRecord& r);
// The limit for a splat of std dev `scale`: the normal turns at most 45 degrees per std dev.
inline float curvature_limit(float scale) { return scale > 0.0f ? 1.0f / scale : 0.0f; }

} // namespace pbdsplat::splat
