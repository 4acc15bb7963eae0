#include "mesh/deformation.h"

#include <algorithm>
#include <cmath>

namespace pbdsplat::mesh {

Eigen::Matrix2f rest_frame_inverse(const Vec3f& a, const Vec3f& b, const Vec3f& c, float min_quality) {
    const Vec3f e1 = b - a, e2 = c - a;
    const float l1 = e1.norm();
    const Vec3f u = l1 > 0.0f ? Vec3f(e1 / l1) : Vec3f::UnitX();
    const Vec3f w = (e2 - e2.dot(u) * u).normalized();
    Eigen::Matrix2f dm;
    dm << l1, e2.dot(u), 0.0f, e2.dot(w);
    const float longest = std::max({l1, e2.norm(), (e2 - e1).norm()});
    const bool sliver = !(std::abs(dm.determinant()) > min_quality * longest * longest);
    return sliver ? Eigen::Matrix2f::Zero() : Eigen::Matrix2f(dm.inverse());
}

float largest_stretch(const Eigen::Matrix2f& rest_inverse, const Vec3f& e1, const Vec3f& e2) {
    return stretches(rest_inverse, e1, e2).largest;
}

Stretch stretches(const Eigen::Matrix2f& rest_inverse, const Vec3f& e1, const Vec3f& e2) {
    Eigen::Matrix<float, 3, 2> ds;
    ds << e1, e2;
    const Eigen::Matrix<float, 3, 2> f = ds * rest_inverse;
    const Eigen::Matrix2f ftf = f.transpose() * f;
    // The eigenvalues of the symmetric 2x2 F^T F: the squared singular values.
    const float tr = ftf.trace(), det = ftf.determinant();
    const float root = std::sqrt(std::max(0.0f, 0.25f * tr * tr - det));
    return {std::sqrt(std::max(0.0f, 0.5f * tr + root)), std::sqrt(std::max(0.0f, 0.5f * tr - root))};
}

} // namespace pbdsplat::mesh
