#include "splat/gaussian_record.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <Eigen/Eigenvalues>

#include "core/assert.h"

namespace pbdsplat::splat {

Vec3f decode_octahedral(const int16_t in[2]) {
    const float x = std::max(float(in[0]) / 32767.0f, -1.0f), y = std::max(float(in[1]) / 32767.0f, -1.0f);
    Vec3f n(x, y, 1.0f - std::abs(x) - std::abs(y));
    if (n.z() < 0.0f) {
        const float ox = (1.0f - std::abs(y)) * detail::sign_not_zero(x);
        const float oy = (1.0f - std::abs(x)) * detail::sign_not_zero(y);
        n.x() = ox, n.y() = oy;
    }
    return n.normalized();
}

GaussianRecord make_record(const Vec3f& position, const Vec3f& normal, const Appearance& a, float fade) {
    GaussianRecord r;
    r.position[0] = position.x();
    r.position[1] = position.y();
    r.position[2] = position.z();
    encode_octahedral(normal, r.normal_oct);
    r.color[0] = to_unorm8(a.albedo.x());
    r.color[1] = to_unorm8(a.albedo.y());
    r.color[2] = to_unorm8(a.albedo.z());
    r.color[3] = to_unorm8(fade);
    r.scale_half = float_to_half(a.scale);
    r.opacity_half = float_to_half(a.opacity_logit);
    for (uint16_t& c : r.curvature_half) c = 0;
    return r;
}

namespace {
// See pack_curvature_w (0 in a record made without a place: never thinned).
int packed_curvature_w(const GaussianRecord& r) { return int(std::lround(half_to_float(r.curvature_half[3]))); }
} // namespace

void set_thin_level(GaussianRecord& r, int level, int rank) { r.curvature_half[3] = pack_curvature_w(curvature_axis(r), level, rank); }
int thin_level(const GaussianRecord& r) { return SPLAT_THIN_LEVELS - ((packed_curvature_w(r) >> 2) & 7); }
int thin_rank(const GaussianRecord& r) { return packed_curvature_w(r) >> 5; }
int curvature_axis(const GaussianRecord& r) { return std::min(packed_curvature_w(r) & 3, 2); }

GaussianShape make_shape(const Eigen::Matrix3f& axes) {
    GaussianShape s;
    for (int k = 0; k < 3; ++k)
        for (int c = 0; c < 3; ++c) s.axes_half[3 * k + c] = float_to_half(axes(c, k));
    return s;
}

Eigen::Matrix3f shape_axes(const GaussianShape& s) {
    Eigen::Matrix3f a;
    for (int k = 0; k < 3; ++k)
        for (int c = 0; c < 3; ++c) a(c, k) = half_to_float(s.axes_half[3 * k + c]);
    return a;
}

float shape_reach(const Eigen::Matrix3f& axes) {
    // The square root of the covariance's largest eigenvalue: the longest principal axis.
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3f> eig(axes * axes.transpose(), Eigen::EigenvaluesOnly);
    return std::sqrt(std::max(eig.eigenvalues().maxCoeff(), 0.0f));
}

namespace {
template <class Point>
void map_any(std::span<const Point> positions, std::span<const Vec3f> normals, const Appearance& a, std::span<GaussianRecord> out) {
    PBDSPLAT_ASSERT(positions.size() == normals.size() && out.size() == positions.size(), "map_points: one normal and one record per position");
    const GaussianRecord base = make_record(Vec3f::Zero(), Vec3f::UnitZ(), a);
    for (size_t i = 0; i < positions.size(); ++i) {
        GaussianRecord r = base;
        r.position[0] = positions[i].x();
        r.position[1] = positions[i].y();
        r.position[2] = positions[i].z();
        encode_octahedral(normals[i], r.normal_oct);
        out[i] = r;
    }
}
} // namespace

void map_points(std::span<const Vec3f> positions, std::span<const Vec3f> normals, const Appearance& a,
                std::vector<GaussianRecord>& out) {
    out.resize(positions.size());
    map_any(positions, normals, a, std::span<GaussianRecord>(out));
}

void map_points(std::span<const Vec4f> positions, std::span<const Vec3f> normals, const Appearance& a, std::span<GaussianRecord> out) {
    map_any(positions, normals, a, out);
}

void map_points(std::span<const Vec4f> positions, std::span<const Vec3f> normals, const Appearance& a,
                std::vector<GaussianRecord>& out) {
    out.resize(positions.size());
    map_any(positions, normals, a, std::span<GaussianRecord>(out));
}

} // namespace pbdsplat::splat
