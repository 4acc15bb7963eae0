#pragma once
// An indexed triangle mesh: positions and counter-clockwise (outward) triangles.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "core/math.h"

namespace pbdsplat::mesh {

using Triangle = std::array<uint32_t, 3>;

struct TriangleMesh {
    std::vector<Vec3f> positions;
    std::vector<Triangle> triangles;
    // Optional per-vertex attributes: each is empty or has one entry per position.
    std::vector<Vec3f> normals;
    std::vector<Vec2f> uvs;
    std::vector<Vec3f> colors;  // linear rgb in [0, 1]

    size_t vertex_count() const { return positions.size(); }
    size_t triangle_count() const { return triangles.size(); }
};

// Appends `part` to `into` as a separate component, its positions (and normals) transformed.
// An attribute either mesh lacks is filled for its vertices: normals and uvs with zeros,
// colours with `fill_color` (so a coloured part next to an uncoloured one keeps its colours).
void append(TriangleMesh& into, const TriangleMesh& part, const Eigen::Affine3f& transform = Eigen::Affine3f::Identity(),
            const Vec3f& fill_color = Vec3f::Ones());

// Axis-aligned bounds; both zero for an empty mesh.
struct Bounds {
    Vec3f min = Vec3f::Zero();
    Vec3f max = Vec3f::Zero();
    Vec3f center() const { return 0.5f * (min + max); }
    float diagonal() const { return (max - min).norm(); }
};
Bounds bounds(std::span<const Vec3f> points);  // zero for none
Bounds bounds(const TriangleMesh& mesh);

// Area-weighted vertex normals (unit length; zero for a vertex no triangle uses).
std::vector<Vec3f> vertex_normals(const TriangleMesh& mesh);

// Mean length of the unique edges: the l_edge of the paper's h = eta * l_edge.
float mean_edge_length(const TriangleMesh& mesh);

// Number of undirected edges used by exactly one triangle (0 for a closed surface).
size_t boundary_edge_count(const TriangleMesh& mesh);

// True when every undirected edge is shared by exactly two triangles with opposite directions:
// a closed, consistently oriented 2-manifold surface.
bool is_closed_and_oriented(const TriangleMesh& mesh);

// Signed volume by the divergence theorem (the paper's equation 9); positive for an
// outward-oriented closed surface.
double signed_volume(const TriangleMesh& mesh);

} // namespace pbdsplat::mesh
