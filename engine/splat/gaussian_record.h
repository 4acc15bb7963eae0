#pragma once
// The contract between the simulation half and the renderer: one packed Gaussian per particle
// or boundary particle (layout in shaders/shared/gpu_types.h, 32 bytes).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/half.h"
#include "core/math.h"
#include "gpu_types.h"

namespace pbdsplat::splat {

struct GaussianRecord {
    float position[3];
    int16_t normal_oct[2];   // snorm16
    uint8_t color[4];        // unorm8 rgb albedo, a = fade
    uint16_t scale_half;     // isotropic std dev s0, IEEE half
    uint16_t opacity_half;   // opacity logit o, IEEE half
    // How the normal turns across the splat (splat/normal_field.h), IEEE half: a 2x2 block of
    // a symmetric 3x3 and the axis it leaves out (gpu_types.h); all zero: one flat normal.
    uint16_t curvature_half[4];
};
static_assert(sizeof(GaussianRecord) == SPLAT_RECORD_SIZE, "GaussianRecord must match SPLAT_RECORD_SIZE");
static_assert(offsetof(GaussianRecord, position) == SPLAT_OFFSET_POSITION);
static_assert(offsetof(GaussianRecord, normal_oct) == SPLAT_OFFSET_NORMAL);
static_assert(offsetof(GaussianRecord, color) == SPLAT_OFFSET_COLOR);
static_assert(offsetof(GaussianRecord, scale_half) == SPLAT_OFFSET_SCALE_OPACITY);
static_assert(offsetof(GaussianRecord, curvature_half) == SPLAT_OFFSET_CURVATURE);

// The axes of an anisotropic Gaussian (SPLAT_SHAPE_SIZE in gpu_types.h), in a stream beside the
// records: only bodies whose splats are not round carry one.
struct GaussianShape {
    uint16_t axes_half[9];  // axis k's x, y, z at 3k..3k+2, IEEE half, world units
    uint16_t pad = 0;
};
static_assert(sizeof(GaussianShape) == SPLAT_SHAPE_SIZE, "GaussianShape must match SPLAT_SHAPE_SIZE");

// Degrees 1-3 of a Gaussian's view-dependent colour (SPLAT_SH_SIZE in gpu_types.h), in a stream
// beside the records: only files trained with them carry one.
struct GaussianSH {
    uint16_t rest_half[SPLAT_SH_COEFFS];  // f_rest_0..44: channel c's coefficient k (1..15) at 15c + k - 1
    uint16_t pad[3] = {0, 0, 0};
};
static_assert(sizeof(GaussianSH) == SPLAT_SH_SIZE, "GaussianSH must match SPLAT_SH_SIZE");

// Where a textured model's texture lies on a splat (SPLAT_TEXCOORD_SIZE in gpu_types.h), in a
// stream beside the records: only scenes whose models are textured carry one.
struct GaussianTexcoord {
    float uv[2] = {0.0f, 0.0f};
    uint16_t gradient_half[6] = {0, 0, 0, 0, 0, 0};  // du x y z, dv x y z (world units), IEEE half
    uint16_t texture = SPLAT_NO_TEXTURE;
    uint16_t reach_half = 0;  // how far from its centre the splat may read (world units), IEEE half
    uint8_t tint[4] = {255, 255, 255, 255};  // unorm8 linear rgb; a unused
    uint32_t pad = 0;
};
static_assert(sizeof(GaussianTexcoord) == SPLAT_TEXCOORD_SIZE, "GaussianTexcoord must match SPLAT_TEXCOORD_SIZE");

using core::float_to_half;
using core::half_to_float;

namespace detail {
inline int16_t to_snorm16(float v) {
    const float s = std::clamp(v, -1.0f, 1.0f) * 32767.0f;
    return int16_t(s >= 0.0f ? s + 0.5f : s - 0.5f);  // round half away from zero, like lround
}
inline float sign_not_zero(float v) { return v >= 0.0f ? 1.0f : -1.0f; }
} // namespace detail

// Octahedral encoding of a unit vector into two snorm16 (error below 1e-4 rad). Inline: the
// mapping encodes every splat's normal every frame.
inline void encode_octahedral(const Vec3f& n, int16_t out[2]) {
    const float l1 = std::abs(n.x()) + std::abs(n.y()) + std::abs(n.z());
    if (!(l1 > 0.0f)) {  // zero or NaN normal: encode +Z rather than propagate garbage
        out[0] = out[1] = 0;
        return;
    }
    float x = n.x() / l1, y = n.y() / l1;
    if (n.z() < 0.0f) {
        const float ox = (1.0f - std::abs(y)) * detail::sign_not_zero(x);
        const float oy = (1.0f - std::abs(x)) * detail::sign_not_zero(y);
        x = ox, y = oy;
    }
    out[0] = detail::to_snorm16(x);
    out[1] = detail::to_snorm16(y);
}
// v in [0, 1] (clamped; NaN as 0) to unorm8, rounded as std::lround rounds: half away from zero.
// Without the library call: the mapping converts every splat's colour every frame.
inline uint8_t to_unorm8(float v) {
    const float x = std::clamp(v, 0.0f, 1.0f) * 255.0f;
    if (!(x >= 0.0f)) return 0;
    const int i = int(x);  // x >= 0: truncation is floor, and x - i is exact
    return uint8_t(i + (x - float(i) >= 0.5f ? 1 : 0));
}
Vec3f decode_octahedral(const int16_t in[2]);

// The record's model (gpu_types.h: the lowest two bits of each normal component; models past
// SPLAT_ENV_CENTERS - 1 are stored as it). Two bits of a 16-bit octahedral component move the
// normal by at most 7e-4 rad (0.04 degrees, where the octahedron folds at -z). -32768 is kept
// out: the shaders read the snorm as a float, which takes -32768 and -32767 alike to -1.
inline void set_model(GaussianRecord& r, uint32_t model) {
    const uint32_t m = std::min<uint32_t>(model, SPLAT_ENV_CENTERS - 1);
    for (int k = 0; k < 2; ++k) {
        int c = (int(r.normal_oct[k]) & ~3) | int((m >> (2 * k)) & 3u);
        if (c < -32767) c += 4;
        r.normal_oct[k] = int16_t(c);
    }
}
inline uint32_t record_model(const GaussianRecord& r) { return uint32_t(r.normal_oct[0] & 3) | (uint32_t(r.normal_oct[1] & 3) << 2); }

struct Appearance {
    Vec3f albedo{0.8f, 0.2f, 0.2f};  // linear rgb
    float opacity_logit = 4.0f;      // sigmoid(4) ~ 0.982
    float scale = 0.05f;             // s0, world units
    bool operator==(const Appearance&) const = default;
};

GaussianRecord make_record(const Vec3f& position, const Vec3f& normal, const Appearance& a, float fade = 1.0f);

// The record's place in the thinning order (surface/thin_order.h): its level (0 to
// SPLAT_THIN_LEVELS) and its rank within the level (0 to 63: the order in which a level's
// splats go while it is thinned out), kept beside the curvature's left-out axis (gpu_types.h);
// either may be set first. A record made without one (particles, cut faces, captures) is at the
// top level: never thinned.
void set_thin_level(GaussianRecord& r, int level, int rank = 0);
int thin_level(const GaussianRecord& r);
int thin_rank(const GaussianRecord& r);
// The curvature's left-out axis (0, 1 or 2).
int curvature_axis(const GaussianRecord& r);
// Entry 3 of the curvature as the shaders read it: an integer below 2048, which a half holds
// exactly: 2 bits of axis, 3 of levels below the top (0: never thinned), 6 of rank.
inline uint16_t pack_curvature_w(int axis, int level, int rank) {
    const int below_top = SPLAT_THIN_LEVELS - std::clamp(level, 0, SPLAT_THIN_LEVELS);
    return core::float_to_half_in_range(float(axis + 4 * below_top + 32 * std::clamp(rank, 0, 63)));
}

// The shape whose covariance is axes * axes^T (columns: the Gaussian's axes, world units).
GaussianShape make_shape(const Eigen::Matrix3f& axes);
Eigen::Matrix3f shape_axes(const GaussianShape& s);
// The longest axis: what the record's scale must say for culling and the depth push.
float shape_reach(const Eigen::Matrix3f& axes);

// One record per point: the paper's one-to-one particle-to-Gaussian mapping (eqs. 11-13).
// Only the centre and the normal vary per point; the rest of the record is packed once.
void map_points(std::span<const Vec3f> positions, std::span<const Vec3f> normals, const Appearance& a,
                std::vector<GaussianRecord>& out);
// The same from float4 positions (the simulation's layout; w ignored).
// The same into `out`, one record per position, without resizing it.
void map_points(std::span<const Vec4f> positions, std::span<const Vec3f> normals, const Appearance& a, std::span<GaussianRecord> out);
void map_points(std::span<const Vec4f> positions, std::span<const Vec3f> normals, const Appearance& a,
                std::vector<GaussianRecord>& out);

} // namespace pbdsplat::splat
