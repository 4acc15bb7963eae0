#include "core/math.h"

#include <cmath>

#include "core/assert.h"

namespace pbdsplat::math {

Mat4f look_at(const Vec3f& eye, const Vec3f& target, const Vec3f& up) {
    const Vec3f view = target - eye;
    PBDSPLAT_ASSERT(view.squaredNorm() > 0.0f && view.allFinite(), "look_at: the eye and the target coincide");
    const Vec3f f = view.normalized();
    // Looking straight along `up` (a camera right above what it looks at) leaves the image's up
    // undefined: any axis across the view serves; this one is what a view slightly off it gives.
    Vec3f up_used = up;
    if (!(std::abs(f.dot(up.normalized())) < 0.9999f)) up_used = (std::abs(f.x()) < 0.9f ? Vec3f::UnitX() : Vec3f::UnitZ()).cross(f);
    const Vec3f s = f.cross(up_used).normalized();
    const Vec3f u = s.cross(f);
    Mat4f m = Mat4f::Identity();
    m.block<1, 3>(0, 0) = s.transpose();
    m.block<1, 3>(1, 0) = u.transpose();
    m.block<1, 3>(2, 0) = -f.transpose();
    m(0, 3) = -s.dot(eye);
    m(1, 3) = -u.dot(eye);
    m(2, 3) = f.dot(eye);
    return m;
}

Mat4f perspective(float fov_y, float aspect, float z_near, float z_far) {
    PBDSPLAT_ASSERT(fov_y > 0.0f && fov_y < k_pi && aspect > 0.0f && z_near > 0.0f && z_far > z_near,
                    "perspective: need 0 < fov_y < pi, aspect > 0 and 0 < near < far");
    const float t = 1.0f / std::tan(fov_y * 0.5f);
    Mat4f p = Mat4f::Zero();
    p(0, 0) = t / aspect;
    p(1, 1) = -t;  // Vulkan's clip y points down
    p(2, 2) = z_far / (z_near - z_far);
    p(2, 3) = z_near * z_far / (z_near - z_far);
    p(3, 2) = -1.0f;
    return p;
}

} // namespace pbdsplat::math
