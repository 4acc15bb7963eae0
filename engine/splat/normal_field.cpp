#include "splat/normal_field.h"

#include <algorithm>
#include <cmath>

namespace pbdsplat::splat {

void tangent_frame(const Vec3f& n, Vec3f& t1, Vec3f& t2) {
    // The same arithmetic as the shader's, so the two pick the same helper axis.
    const Vec3f helper = std::abs(n.x()) < 0.9f ? Vec3f::UnitX() : Vec3f::UnitY();
    t1 = n.cross(helper).normalized();
    t2 = n.cross(t1);
}

void NormalField::update(std::span<const Vec4f> x, std::span<const Vec3f> vertex_normals,
                         std::span<const mesh::Triangle> triangles, bool vertices) {
    triangle_.resize(triangles.size());
    if (vertices) {
        vertex_.assign(x.size(), Mat3f::Zero());
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
        Mat3f d = Mat3f::Zero();
        // dn/dx = [n1-n0, n2-n0] (G^T G)^-1 G^T with G = [e1 e2]: exact for the linear field on
        // the triangle's plane, zero along its normal. A sliver's inverse is noise: no turn.
        if (det > 1e-6f * a * c && det > 0.0f) {
            const Vec3f dn1 = vertex_normals[tri[1]] - vertex_normals[tri[0]];
            const Vec3f dn2 = vertex_normals[tri[2]] - vertex_normals[tri[0]];
            const float inv = 1.0f / det;
            // Rows of (G^T G)^-1 G^T: (c e1 - b e2) / det and (a e2 - b e1) / det.
            const Vec3f r1 = (c * e1 - b * e2) * inv, r2 = (a * e2 - b * e1) * inv;
            d = dn1 * r1.transpose() + dn2 * r2.transpose();
        }
        triangle_[t] = d;
        if (vertices) {
            const float area = std::sqrt(std::max(det, 0.0f));
            for (uint32_t v : tri) {
                vertex_[v] += area * d;
                weight_[v] += area;
            }
        }
    }
    if (vertices)
        for (size_t v = 0; v < vertex_.size(); ++v)
            if (weight_[v] > 0.0f) vertex_[v] /= weight_[v];
}

void encode_curvature(const Mat3f& dndx, float limit, GaussianRecord& r) {
    Vec3f t1, t2;
    tangent_frame(decode_octahedral(r.normal_oct), t1, t2);
    const Vec3f d1 = dndx * t1, d2 = dndx * t2;
    const float m[3] = {t1.dot(d1), 0.5f * (t1.dot(d2) + t2.dot(d1)), t2.dot(d2)};
    for (int k = 0; k < 3; ++k) {
        const float v = std::isfinite(m[k]) ? std::clamp(m[k], -limit, limit) : 0.0f;
        r.curvature_half[k] = float_to_half(v);
    }
}

Vec3f decode_curvature(const GaussianRecord& r) {
    return Vec3f(half_to_float(r.curvature_half[0]), half_to_float(r.curvature_half[1]), half_to_float(r.curvature_half[2]));
}

} // namespace pbdsplat::splat
