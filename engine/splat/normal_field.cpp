#include "splat/normal_field.h"

#include <algorithm>
#include <cmath>

namespace pbdsplat::splat {

namespace {
// xx, xy, xz, yy, yz, zz of a symmetric matrix.
constexpr int k_row[6] = {0, 0, 0, 1, 1, 2}, k_col[6] = {0, 1, 2, 1, 2, 2};
} // namespace

PackedCurvature pack_curvature(const Mat3f& s, float limit) {
    // Within what a half holds, so the fast conversion applies.
    limit = std::min(limit, 60000.0f);
    PackedCurvature c;
    for (int k = 0; k < 6; ++k) {
        const float v = s(k_row[k], k_col[k]);
        c[size_t(k)] = core::float_to_half_in_range(std::isfinite(v) ? std::clamp(v, -limit, limit) : 0.0f);
    }
    return c;
}

Mat3f decode_curvature(const GaussianRecord& r) {
    Mat3f s;
    for (int k = 0; k < 6; ++k) s(k_row[k], k_col[k]) = s(k_col[k], k_row[k]) = half_to_float(r.curvature_half[k]);
    return s;
}

void NormalField::update(std::span<const Vec4f> x, std::span<const Vec3f> vertex_normals,
                         std::span<const mesh::Triangle> triangles, bool vertices, float limit) {
    triangle_.resize(triangles.size());
    if (vertices) {
        vertex_sum_.assign(x.size(), {});
        weight_.assign(x.size(), 0.0f);
    } else {
        vertex_sum_.clear();
        vertex_.clear();
    }
    for (size_t t = 0; t < triangles.size(); ++t) {
        const auto& tri = triangles[t];
        const Vec3f p0 = x[tri[0]].head<3>();
        const Vec3f e1 = x[tri[1]].head<3>() - p0, e2 = x[tri[2]].head<3>() - p0;
        const float a = e1.dot(e1), b = e1.dot(e2), c = e2.dot(e2);
        const float det = a * c - b * b;  // |e1 x e2|^2
        Mat3f s = Mat3f::Zero();
        // dn/dx = [n1-n0, n2-n0] (G^T G)^-1 G^T with G = [e1 e2]: exact for the linear field on
        // the triangle's plane. Its outputs are projected onto the plane (the part that turns the
        // normal rather than lengthening it) and the whole symmetrised, as a shape operator is.
        // A sliver's inverse is noise: no turn.
        if (det > 1e-6f * a * c && det > 0.0f) {
            const Vec3f n = e1.cross(e2) / std::sqrt(det);
            Vec3f dn1 = vertex_normals[tri[1]] - vertex_normals[tri[0]];
            Vec3f dn2 = vertex_normals[tri[2]] - vertex_normals[tri[0]];
            dn1 -= dn1.dot(n) * n;
            dn2 -= dn2.dot(n) * n;
            const float inv = 1.0f / det;
            // Rows of (G^T G)^-1 G^T: (c e1 - b e2) / det and (a e2 - b e1) / det.
            const Vec3f r1 = (c * e1 - b * e2) * inv, r2 = (a * e2 - b * e1) * inv;
            const Mat3f d = dn1 * r1.transpose() + dn2 * r2.transpose();
            s = 0.5f * (d + d.transpose());
        }
        triangle_[t] = pack_curvature(s, limit);
        if (vertices) {
            const float area = std::sqrt(std::max(det, 0.0f));
            for (uint32_t v : tri) {
                for (int k = 0; k < 6; ++k) vertex_sum_[v][size_t(k)] += area * s(k_row[k], k_col[k]);
                weight_[v] += area;
            }
        }
    }
    if (!vertices) return;
    vertex_.resize(x.size());
    for (size_t v = 0; v < x.size(); ++v) {
        const float w = weight_[v] > 0.0f ? 1.0f / weight_[v] : 0.0f;
        Mat3f s;
        for (int k = 0; k < 6; ++k) s(k_row[k], k_col[k]) = s(k_col[k], k_row[k]) = w * vertex_sum_[v][size_t(k)];
        vertex_[v] = pack_curvature(s, limit);
    }
}

} // namespace pbdsplat::splat
