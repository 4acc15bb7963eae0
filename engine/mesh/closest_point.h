#pragma once
// Closest points on a triangle mesh: the exact point-triangle query and a uniform grid over
// the triangles to find the ones near a point. Embedding a fine surface in a coarse one asks
// this hundreds of thousands of times, so the grid is flat arrays (CSR cells), not a tree.
#include <cstdint>
#include <span>
#include <vector>

#include "mesh/triangle_mesh.h"

namespace pbdsplat::mesh {

// The point of triangle (a, b, c) closest to p, as barycentric weights of b and c.
Vec2f closest_point_barycentric(const Vec3f& p, const Vec3f& a, const Vec3f& b, const Vec3f& c);

// A triangle's closest point to a query: the distance, the triangle, and the point as
// barycentric weights of its corners 1 and 2.
struct ClosestPoint {
    float distance;
    uint32_t triangle;
    Vec2f bary;
};

class TriangleGrid {
public:
    // Cells about as large as the triangles; the mesh must outlive the grid.
    TriangleGrid(std::span<const Vec3f> positions, std::span<const Triangle> triangles);

    // Triangles that may lie within `radius` of p (every one that does, and some more). The
    // queries keep no state: threads may share a grid.
    void near(const Vec3f& p, float radius, std::vector<uint32_t>& out) const;
    // Every triangle whose closest point lies within `factor` x the nearest distance + `margin`
    // of p, nearest first (ties by index): the nearest and its rivals, searched outwards.
    void closest(const Vec3f& p, float factor, float margin, std::vector<ClosestPoint>& out) const;
    // The distance from p to the mesh (exact).
    float distance(const Vec3f& p) const;
    float cell_size() const { return cell_; }

private:
    Eigen::Vector3i cell_of(const Vec3f& p) const;
    std::span<const Vec3f> positions_;
    std::span<const Triangle> triangles_;
    Vec3f origin_ = Vec3f::Zero();
    Eigen::Vector3i dims_ = Eigen::Vector3i::Ones();
    float cell_ = 1.0f;
    std::vector<uint32_t> start_;  // per cell, into items_
    std::vector<uint32_t> items_;  // triangle indices
    std::vector<Eigen::Vector3i> lowest_cell_;  // per triangle: the cell of its box's low corner
    std::vector<Vec4f> spheres_;  // per triangle: a sphere around it (centre, radius)
};

} // namespace pbdsplat::mesh
