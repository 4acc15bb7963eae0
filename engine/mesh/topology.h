#pragma once
// Connectivity derived from a triangle list: unique edges, boundary loops and components.
#include <cstdint>
#include <span>
#include <vector>

#include "mesh/triangle_mesh.h"

namespace pbdsplat::mesh {

struct Edge {
    uint32_t a, b;  // a < b
};

// Every undirected edge once, sorted by (a, b): deterministic, and local once vertices are.
std::vector<Edge> unique_edges(const TriangleMesh& mesh);

// Closed boundary loops of a manifold-with-boundary mesh, each a vertex list in the direction
// of its triangles' boundary edges (so a cap fan over it has the mesh's orientation reversed).
std::vector<std::vector<uint32_t>> boundary_loops(const TriangleMesh& mesh);

// Component id of each triangle (connected through shared edges), ids from 0 in order of
// first triangle; returns the number of components.
uint32_t triangle_components(const TriangleMesh& mesh, std::vector<uint32_t>& component_of_triangle);

// The same from a bare triangle list over `vertex_count` vertices (no copy of a mesh needed).
std::vector<std::vector<uint32_t>> boundary_loops(std::span<const Triangle> triangles, size_t vertex_count);

// Components through shared vertices, with plain arrays (cheap on large meshes): equal to
// components through shared edges on meshes without bow-ties, which the topology stage keeps.
uint32_t vertex_components(std::span<const Triangle> triangles, size_t vertex_count,
                           std::vector<uint32_t>& component_of_triangle);

} // namespace pbdsplat::mesh
