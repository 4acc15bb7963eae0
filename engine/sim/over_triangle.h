#pragma once
// Where a point lies over a triangle: what contact and the fold guard both ask of a candidate.
#include "mesh/closest_point.h"
#include "sim/particles.h"

namespace pbdsplat::sim {

template <class Real>
inline Vec3f pos3(const Vec4<Real>& v) { return v.template head<3>().template cast<float>(); }

// The closest point's weights of a, b, c, the signed distance along the unit normal n, and how
// far the closest point lies beside p's projection (0: p lies over the triangle).
struct Over {
    float wa, wb, wc;
    float height;   // (p - q) . n
    float lateral;  // |(p - q) - height n|
};
inline Over over_triangle(const Vec3f& p, const Vec3f& a, const Vec3f& b, const Vec3f& c, const Vec3f& n) {
    const Vec2f w = mesh::closest_point_barycentric(p, a, b, c);
    const Vec3f q = a + w.x() * (b - a) + w.y() * (c - a);
    const Vec3f d = p - q;
    const float height = d.dot(n);
    return {1.0f - w.x() - w.y(), w.x(), w.y(), height, (d - height * n).norm()};
}
// How far beside a triangle (over the mean edge length) a point still counts as over it: the
// rounding of a point projected onto an edge two triangles share.
inline constexpr float k_over = 0.01f;
inline Vec3f unit_normal(const Vec3f& a, const Vec3f& b, const Vec3f& c) {
    const Vec3f n = (b - a).cross(c - a);
    const float len = n.norm();
    return len > 0.0f ? Vec3f(n / len) : Vec3f::Zero();
}

} // namespace pbdsplat::sim
