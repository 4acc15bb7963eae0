#pragma once
// How much a triangle is stretched: its deformation gradient F = Ds Dm^-1 in its own rest
// frame, and F's largest singular value (the stretch along the most stretched direction). Used
// to grow splats with their triangle and to resample the surface where it stretched.
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

} // namespace pbdsplat::mesh
