#pragma once
// Makes any triangle soup usable by the solver: welded, without degenerate or duplicate
// triangles, consistently oriented (outward), manifold with boundary. Reports what it changed.
#include <string>
#include <vector>

#include "core/result.h"
#include "mesh/triangle_mesh.h"

namespace pbdsplat::mesh {

struct RepairOptions {
    // Vertices closer than this fraction of the bounding-box diagonal are welded; 0 disables.
    float weld_tolerance = 1e-5f;
    bool center = false;          // move the bounding-box centre to the origin
    float fit_diagonal = 0.0f;    // > 0: scale so the bounding-box diagonal has this length
    float scale = 1.0f;           // then multiply positions by this
    // Caps every boundary loop with a fan around its centroid, so an open model (the teapot's
    // lid rim and spout) can hold air: a balloon needs a closed surface.
    bool close_holes = false;
};

struct RepairReport {
    size_t input_vertices = 0, input_triangles = 0;
    size_t welded_vertices = 0;          // vertices merged into another
    size_t unreferenced_vertices = 0;    // dropped: no triangle used them
    size_t degenerate_triangles = 0;     // dropped: repeated corner or zero area
    size_t duplicate_triangles = 0;      // dropped: same three vertices as an earlier one
    size_t nonmanifold_edges = 0;        // edges with more than two triangles, split apart
    size_t split_vertices = 0;           // vertex copies made to separate fans
    size_t flipped_triangles = 0;        // reversed for consistent, outward orientation
    size_t boundary_edges = 0, boundary_loops = 0;  // after capping, with close_holes
    size_t capped_holes = 0;
    size_t components = 0, closed_components = 0;
    size_t output_vertices = 0, output_triangles = 0;

    std::string summary() const;  // one line for logs
};

struct RepairedMesh {
    TriangleMesh mesh;
    RepairReport report;
    // The centring and scaling applied: an input point p is now (p + shift) * scale.
    Vec3f shift = Vec3f::Zero();
    float scale = 1.0f;
};

// `name` is used in error messages (the file the mesh came from). Fails when nothing usable
// remains (no triangles, or all of them degenerate), or on non-finite positions.
core::Result<RepairedMesh> repair(TriangleMesh mesh, const RepairOptions& options, const std::string& name);

} // namespace pbdsplat::mesh
