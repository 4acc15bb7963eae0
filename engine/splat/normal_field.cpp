#include "splat/normal_field.h"

#include <algorithm>
#include <cmath>

namespace pbdsplat::splat {

namespace {
// xx, xy, xz, yy, yz, zz of a symmetric matrix.
constexpr int k_row[6] = {0, 0, 0, 1, 1, 2}, k_col[6] = {0, 1, 2, 1, 2, 2};
// Index of (r, c) in SymmetricCurvature.
constexpr int k_index[3][3] = {{0, 1, 2}, {1, 3, 4}, {2, 4, 5}};
} // namespace

Mat3f to_matrix(const SymmetricCurvature& s) {
    Mat3f m;
    for (int k = 0; k < 6; ++k) m(k_row[k], k_col[k]) = m(k_col[k], k_row[k]) = s[size_t(k)];
    return m;
}

SymmetricCurvature to_symmetric(const Mat3f& m, float limit) {
    // Within what a half holds, so the fast conversion applies when it is packed.
    limit = std::min(limit, 60000.0f);
    SymmetricCurvature s;
    for (int k = 0; k < 6; ++k) {
        const float v = m(k_row[k], k_col[k]);
        s[size_t(k)] = std::isfinite(v) ? std::clamp(v, -limit, limit) : 0.0f;
    }
    return s;
}

int set_curvature_entries(const SymmetricCurvature& s, const Vec3f& n, GaussianRecord& r) {
    // The axis left out is stored, so the shader never has to decide between two near-equal
    // components of its own (decoded) normal.
    const Vec3f a = n.cwiseAbs();
    const int d = a.x() >= a.y() && a.x() >= a.z() ? 0 : a.y() >= a.z() ? 1 : 2;
    const int i = (d + 1) % 3, j = (d + 2) % 3;
    r.curvature_half[0] = core::float_to_half_in_range(s[size_t(k_index[i][i])]);
    r.curvature_half[1] = core::float_to_half_in_range(s[size_t(k_index[i][j])]);
    r.curvature_half[2] = core::float_to_half_in_range(s[size_t(k_index[j][j])]);
    return d;
}

void set_curvature(const SymmetricCurvature& s, const Vec3f& n, GaussianRecord& r) {
    const int level = thin_level(r), rank = thin_rank(r);
    r.curvature_half[3] = pack_curvature_w(set_curvature_entries(s, n, r), level, rank);
}

Mat3f decode_curvature(const GaussianRecord& r) {
    const Vec3f n = decode_octahedral(r.normal_oct);
    const int d = curvature_axis(r);
    const int i = (d + 1) % 3, j = (d + 2) % 3;
    const float a = half_to_float(r.curvature_half[0]), b = half_to_float(r.curvature_half[1]),
                c = half_to_float(r.curvature_half[2]);
    if (a == 0.0f && b == 0.0f && c == 0.0f) return Mat3f::Zero();  // flat, as the shader reads it
    // S n = 0 gives the column of d, then its diagonal entry (as splat_curvature in the shader).
    const float id = -(a * n[i] + b * n[j]) / n[d], jd = -(b * n[i] + c * n[j]) / n[d];
    const float dd = -(id * n[i] + jd * n[j]) / n[d];
    Mat3f m;
    m(i, i) = a, m(j, j) = c, m(d, d) = dd;
    m(i, j) = m(j, i) = b;
    m(i, d) = m(d, i) = id;
    m(j, d) = m(d, j) = jd;
    return m;
}

void NormalField::update(std::span<const Vec4f> x, std::span<const Vec3f> vertex_normals,
                         std::span<const mesh::Triangle> triangles, bool vertices, float limit) {
    triangle_.resize(triangles.size());
    if (vertices) {
        vertex_.assign(x.size(), SymmetricCurvature{});
        weight_.assign(x.size(), 0.0f);
    } else {
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
        triangle_[t] = to_symmetric(s, limit);
        if (vertices) {
            const float area = std::sqrt(std::max(det, 0.0f));
            for (uint32_t v : tri) {
                for (size_t k = 0; k < 6; ++k) vertex_[v][k] += area * triangle_[t][k];
                weight_[v] += area;
            }
        }
    }
    if (vertices)
        for (size_t v = 0; v < x.size(); ++v) {
            const float w = weight_[v] > 0.0f ? 1.0f / weight_[v] : 0.0f;
            for (float& e : vertex_[v]) e *= w;
        }
}

} // namespace pbdsplat::splat
