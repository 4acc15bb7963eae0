#pragma once
// Boundary particles (paper sections 4.2 and 5.3): samples of the surface, at least h apart
// and leaving no point of it farther than about h from a sample, with h = eta * l_edge (eq. 3).
// Each is stored as (triangle, barycentric coordinates) and follows the deforming mesh:
// x = sum b_i x_i, n = normalise(sum b_i n_i). The mesh vertices (the simulation particles)
// count as samples too, so boundary particles fill the space between them.
#include <cstdint>
#include <span>
#include <vector>

#include "core/math.h"
#include "mesh/triangle_mesh.h"

namespace pbdsplat::surface {

struct BoundaryParticles {
    // Compact arrays, one entry per sample.
    std::vector<uint32_t> triangle;
    std::vector<Vec2f> bary;  // (b1, b2); b0 = 1 - b1 - b2
    // Updated every frame.
    std::vector<Vec3f> position;
    std::vector<Vec3f> normal;

    size_t size() const { return triangle.size(); }
    void clear();
};

struct SamplingOptions {
    float h = 0.05f;         // minimum spacing
    uint32_t seed = 1;       // same seed, same samples
    float candidates = 48.0f;  // candidate points per h^2 of area: enough that no gap wider than about h stays
};

// The spacing for a mesh: eta times its mean rest edge length.
float spacing(const mesh::TriangleMesh& mesh, float eta);

// Samples the whole surface. The mesh's vertices act as samples already placed.
BoundaryParticles sample_surface(const mesh::TriangleMesh& mesh, const SamplingOptions& options);

// Adds samples on the given triangles only, keeping h away from every sample already present
// (anywhere) and from the vertices; existing samples do not move. For local resampling after a
// cut or tear.
void fill_triangles(const mesh::TriangleMesh& mesh, std::span<const uint32_t> triangles, const SamplingOptions& options,
                    BoundaryParticles& samples);
// The same on a surface given as rest positions and triangles (a body's, without copying them).
void fill_triangles(std::span<const Vec3f> positions, std::span<const mesh::Triangle> all_triangles,
                    std::span<const uint32_t> triangles, const SamplingOptions& options, BoundaryParticles& samples);

// Moves every sample onto the deformed surface: positions from `x` (one float4 per mesh vertex,
// w ignored), normals from the vertex normals.
void update_boundary_particles(std::span<const mesh::Triangle> triangles, std::span<const Vec4f> x,
                               std::span<const Vec3f> vertex_normals, BoundaryParticles& samples);

} // namespace pbdsplat::surface
