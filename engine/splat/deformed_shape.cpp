#include "splat/deformed_shape.h"

#include <algorithm>
#include <cmath>

#include "mesh/deformation.h"

namespace pbdsplat::splat {

DeformedShapes::DeformedShapes(std::span<const Vec3f> rest, std::span<const mesh::Triangle> triangles) {
    inverse_rest_.resize(triangles.size());
    for (size_t t = 0; t < triangles.size(); ++t)
        inverse_rest_[t] = mesh::rest_frame_inverse(rest[triangles[t][0]], rest[triangles[t][1]], rest[triangles[t][2]]);
    gradient_.assign(triangles.size(), Eigen::Matrix<float, 3, 2>::Zero());
    largest_.assign(triangles.size(), 0.0f);
}

void DeformedShapes::update(std::span<const Vec4f> x, std::span<const mesh::Triangle> triangles) {
    for (size_t t = 0; t < triangles.size(); ++t) {
        Eigen::Matrix<float, 3, 2> ds;
        ds.col(0) = (x[triangles[t][1]] - x[triangles[t][0]]).head<3>();
        ds.col(1) = (x[triangles[t][2]] - x[triangles[t][0]]).head<3>();
        gradient_[t] = ds * inverse_rest_[t];
        largest_[t] = mesh::largest_stretch(inverse_rest_[t], ds.col(0), ds.col(1));
    }
}

void DeformedShapes::map(size_t particles, const surface::BoundaryParticles* samples, std::vector<GaussianRecord>& records,
                         std::vector<GaussianShape>& out) const {
    out.resize(records.size());
    for (size_t i = 0; i < particles; ++i) out[i] = make_shape(half_to_float(records[i].scale_half) * Eigen::Matrix3f::Identity());
    const size_t m = samples ? samples->size() : 0;
    for (size_t k = 0; k < m; ++k) {
        GaussianRecord& r = records[particles + k];
        const uint32_t t = samples->triangle[k];
        // F below carries the triangle's stretch; the growth a round splat takes for it
        // (BoundaryParticles::triangle_growth) would count it twice.
        const float s = half_to_float(r.scale_half) / samples->growth_of(t);
        const Vec3f n = samples->normal[k];
        Eigen::Matrix<float, 3, 2> f = gradient_[t];
        // The sample's own tangent plane (a fine surface riding a coarse triangle tilts away
        // from it): F's axes with their normal part taken out.
        for (int c = 0; c < 2; ++c) f.col(c) -= f.col(c).dot(n) * n;
        const float largest = largest_[t];  // of F before the projection, which only shortens
        Eigen::Matrix3f axes;
        if (!(largest > 1e-3f) || !std::isfinite(largest)) {
            axes = s * Eigen::Matrix3f::Identity();  // a sliver's gradient says nothing: stay round
        } else {
            if (largest > k_max_stretch) f *= k_max_stretch / largest;
            axes.col(0) = s * f.col(0);
            axes.col(1) = s * f.col(1);
            axes.col(2) = s * k_flatness * n;
        }
        out[particles + k] = make_shape(axes);
        r.scale_half = float_to_half(shape_reach(axes));
    }
}

} // namespace pbdsplat::splat
