#pragma once
// How much a triangle is stretched: its deformation gradient F = Ds Dm^-1 in its own rest
// frame, and F's largest singular value (the stretch along the most stretched direction). Used
// to grow splats with their triangle and to resample the surface where it stretched.
#include <algorithm>
#include <cmath>

#include "core/math.h"

namespace pbdsplat::mesh {

// Dm^-1 of the rest triangle (a, b, c) in an orthonormal frame of its plane; zero for a sliver
// (twice its area below `min_quality` times its longest edge squared), whose ill-conditioned
// frame would read a tiny movement as a huge stretch.
Eigen::Matrix2f rest_frame_inverse(const Vec3f& a, const Vec3f& b, const Vec3f& c, float min_quality = 0.02f);

// The largest singular value of F for deformed edges e1 = b - a, e2 = c - a.
float largest_stretch(const Eigen::Matrix2f& rest_inverse, const Vec3f& e1, const Vec3f& e2);

// Both singular values of F: the stretch along the most and the least stretched directions.
struct Stretch {
    float largest = 1.0f, smallest = 1.0f;
};
Stretch stretches(const Eigen::Matrix2f& rest_inverse, const Vec3f& e1, const Vec3f& e2);

// The same squared (the eigenvalues of F^T F), with one square root instead of three: for a
// test against thresholds over every triangle of a body each frame (the density control).
inline Stretch squared_stretches(const Eigen::Matrix2f& m, const Vec3f& e1, const Vec3f& e2) {
    // F^T F = M^T (Ds^T Ds) M with the deformed edges' Gram matrix.
    const float g11 = e1.dot(e1), g12 = e1.dot(e2), g22 = e2.dot(e2);
    const float a = m(0, 0), b = m(0, 1), c = m(1, 0), d = m(1, 1);
    const float p11 = a * a * g11 + 2.0f * a * c * g12 + c * c * g22;
    const float p22 = b * b * g11 + 2.0f * b * d * g12 + d * d * g22;
    const float p12 = a * b * g11 + (a * d + b * c) * g12 + c * d * g22;
    const float half = 0.5f * (p11 + p22), diff = 0.5f * (p11 - p22);
    const float root = std::sqrt(diff * diff + p12 * p12);
    return {half + root, std::max(0.0f, half - root)};
}

} // namespace pbdsplat::mesh
