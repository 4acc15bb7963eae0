#pragma once
// Math vocabulary of the engine: Eigen's fixed-size types under short names, and the camera
// matrices in Vulkan's conventions (right-handed view looking down -Z, clip depth in [0, 1],
// clip-space y pointing down).
#include <algorithm>
#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace pbdsplat {

using Vec2f = Eigen::Vector2f;
using Vec3f = Eigen::Vector3f;
using Vec4f = Eigen::Vector4f;
using Vec3d = Eigen::Vector3d;
using Mat3f = Eigen::Matrix3f;
using Mat4f = Eigen::Matrix4f;
using Quatf = Eigen::Quaternionf;

constexpr float k_pi = 3.14159265358979323846f;

namespace math {

// World-to-view transform of a camera at `eye` looking at `target` (not at `eye`), `up` on the
// image's upward side (any axis across the view where `up` lies along it).
Mat4f look_at(const Vec3f& eye, const Vec3f& target, const Vec3f& up);

// Perspective projection to Vulkan clip space; `fov_y` in radians, reversed nothing, z in [0,1].
Mat4f perspective(float fov_y, float aspect, float z_near, float z_far);

inline float radians(float degrees) { return degrees * (k_pi / 180.0f); }

// Logistic sigmoid: maps an opacity logit to [0, 1] (the paper's equation 21).
inline float sigmoid(float x) { return 1.0f / (1.0f + std::exp(-x)); }
inline float logit(float p) { return std::log(p / (1.0f - p)); }

// 0 at e0, 1 at e1 (either order), with zero slope at both ends: GLSL's smoothstep, so CPU
// models of the shaders match them.
inline float smoothstep(float e0, float e1, float v) {
    const float t = std::clamp((v - e0) / (e1 - e0), 0.0f, 1.0f);
    return t * t * (3.0f - 2.0f * t);
}

// floor() of each coordinate as integers, for grid cells. Truncate, then step down where that
// went up: the same as std::floor and a cast, without the library call that floor costs on SSE2
// (no roundps before SSE4.1; the spatial grids take it three times per point).
inline int floor_to_int(float v) {
    const int i = int(v);
    return i - int(float(i) > v);
}
inline Eigen::Vector3i floor_to_int(const Vec3f& v) {
#if defined(__SSE2__)
    // The three at once, the same steps in SSE lanes: a grid query takes a cell per point, and
    // the crowd check queries every sample kept as it is (23 instructions a point one lane at a
    // time).
    const __m128 f = _mm_setr_ps(v.x(), v.y(), v.z(), 0.0f);
    const __m128i i = _mm_cvttps_epi32(f);
    const __m128i up = _mm_castps_si128(_mm_cmpgt_ps(_mm_cvtepi32_ps(i), f));  // -1 where truncating went up
    alignas(16) int out[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(out), _mm_add_epi32(i, up));
    return {out[0], out[1], out[2]};
#else
    return {floor_to_int(v.x()), floor_to_int(v.y()), floor_to_int(v.z())};
#endif
}

} // namespace math
} // namespace pbdsplat
