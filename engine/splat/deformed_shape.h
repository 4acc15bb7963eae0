#pragma once
// Splats whose covariance follows the surface (render.splat_shape = "deformed"; the paper's
// limitation 7.5.2): each boundary particle's Gaussian is a flat disc in the surface's tangent
// plane, carried by its triangle's deformation gradient F, so it stretches and shears with the
// surface instead of staying round (or growing round, as StretchScale does).
#include <span>
#include <vector>

#include "mesh/triangle_mesh.h"
#include "splat/gaussian_record.h"
#include "surface/boundary_particles.h"

namespace pbdsplat::splat {

class DeformedShapes {
public:
    // The normal axis's share of the splat's size: flat, but not so flat that a disc seen
    // edge-on vanishes between pixels (the projection adds a 0.3-pixel low-pass as well).
    static constexpr float k_flatness = 0.2f;
    // Past this stretch a splat stops following (a torn flap's last threads): it would smear.
    static constexpr float k_max_stretch = 3.0f;

    DeformedShapes() = default;
    DeformedShapes(std::span<const Vec3f> rest_positions, std::span<const mesh::Triangle> triangles);
    bool empty() const { return inverse_rest_.empty(); }

    // F = Ds Dm^-1 of every triangle for the current positions.
    void update(std::span<const Vec4f> x, std::span<const mesh::Triangle> triangles);

    // One shape per record, for records laid out as map_body lays them: `particles` round ones
    // first (their own scale), then one per boundary particle. Each record's scale becomes its
    // shape's longest axis (what culling and the visibility pass's push read).
    void map(size_t particles, const surface::BoundaryParticles* samples, std::vector<GaussianRecord>& records,
             std::vector<GaussianShape>& out) const;

private:
    std::vector<Eigen::Matrix2f> inverse_rest_;  // Dm^-1 in each triangle's rest frame; zero for a sliver
    std::vector<Eigen::Matrix<float, 3, 2>> gradient_;
    std::vector<float> largest_;  // F's largest singular value
};

} // namespace pbdsplat::splat
