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

// Fast forms for meshes known to be manifold with boundary and free of bow-ties (what the
// topology stage keeps): plain arrays instead of hash maps, so a cut on a large mesh stays
// cheap. Loops follow the same direction convention as boundary_loops above; components
// through shared vertices equal components through shared edges when there are no bow-ties.
std::vector<std::vector<uint32_t>> boundary_loops(std::span<const Triangle> triangles, size_t vertex_count);
uint32_t vertex_components(std::span<const Triangle> triangles, size_t vertex_count,
                           std::vector<uint32_t>& component_of_triangle);

} // namespace pbdsplat::mesh
