#pragma once
// The model's full-resolution surface as the simulation mesh carries it now (a decimated body
// under a fine surface): its vertices embedded in the simulation triangles like the samples,
// made on the first call (only coverage checks and mesh occluders ask). Triangles a cut or tear
// tore across (corners on different pieces, or on body triangles torn apart between them, or an
// edge stretched past 3x) are left out.
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "mesh/triangle_mesh.h"
#include "sim/soft_body.h"
#include "surface/boundary_particles.h"

namespace pbdsplat::scene {

// Which fine triangles a cut or tear left whole: it changes only with the body's topology, so a
// caller that draws every frame keeps it between calls.
struct FineTriangles {
    size_t body_triangles = SIZE_MAX, particles = 0, pieces = 0;  // the body they were judged for
    std::vector<mesh::Triangle> whole;
    std::vector<std::array<float, 3>> rest2;  // per whole triangle, (3 x its rest edge)^2, edge k from corner k

    // Where above 0 (the mesh occluders), the whole triangles are drawn simplified within this
    // many world units of the fine surface (mesh::simplify_triangles), the openings' edges kept
    // where they are, once the topology has held for `settle_frames` frames: a tear every few
    // frames would otherwise simplify the surface again each time. Until then, the whole ones.
    float simplify_error = 0.0f;
    uint32_t settle_frames = 10;
    uint32_t frames_held = 0;  // frames since the topology last changed
    bool simplified_current = false;
    std::vector<mesh::Triangle> simplified;
    std::vector<std::array<float, 3>> simplified_rest2;
    // A simplification is asked for and not yet made (the topology has not held long enough).
    bool simplification_due() const { return simplify_error > 0.0f && !simplified_current; }
};

// The models of a scene that the fine surface holds only a copy of: simulated on their own
// vertices beside a decimated model (a procedural table under a teapot), their meshes as they
// were at load. The body's own triangles stand for them: a fine triangle that a cut crossed is
// left out whole, and a copied one is as large as the body's (a stroke across the table left a
// hole of two of its triangles in the occluders, and the splats there were dropped).
struct FineCopies {
    std::vector<std::pair<uint32_t, uint32_t>> triangles;  // the copies' fine triangles, [first, last)
    std::vector<uint8_t> model;                           // per model: the fine surface copies it
    bool any() const { return !triangles.empty(); }
    bool copied(uint32_t fine_triangle) const;
};

// The fine surface as the body carries it now, in `x` and `triangles`. Where `copies` has any,
// the body's particles follow the fine vertices in `x`, and its triangles of the copied models
// (their indices past the fine vertices) follow the fine ones.
void deformed_fine_surface(const sim::SoftBody& body, const mesh::TriangleMesh& fine, const FineCopies& copies,
                           std::optional<surface::BoundaryParticles>& fine_vertices, std::vector<Vec4f>& x,
                           std::vector<mesh::Triangle>& triangles, FineTriangles* keep = nullptr);

// The surface's vertices marked with their model in w (the mesh raster lights each model from its
// own centre, as the splats are: gpu_types.h): `x` as deformed_fine_surface gives it, or the
// body's particles where `fine_vertices` is null. Nothing changes for a body of one model.
void mark_vertex_models(const sim::SoftBody& body, const surface::BoundaryParticles* fine_vertices, std::span<Vec4f> x);
// The body's particles so marked.
std::vector<Vec4f> particles_with_models(const sim::SoftBody& body);

} // namespace pbdsplat::scene
