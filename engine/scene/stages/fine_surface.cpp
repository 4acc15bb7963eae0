#include "scene/stages/fine_surface.h"

#include "mesh/topology.h"
#include "sim/integrate.h"
#include "surface/embedding.h"

namespace pbdsplat::scene {

void deformed_fine_surface(const sim::SoftBody& body, const mesh::TriangleMesh& fine, std::optional<surface::BoundaryParticles>& fine_vertices,
                           std::vector<Vec4f>& x, std::vector<mesh::Triangle>& triangles) {
    if (!fine_vertices) {
        // Embedded on demand: only coverage checks ask. Before any cut the rest mesh is the
        // one the samples were embedded in; after one, its children hold the same surface.
        const std::vector<Vec3f> normals = mesh::vertex_normals(fine);
        std::vector<surface::SurfacePoint> points(fine.positions.size());
        for (size_t i = 0; i < points.size(); ++i) points[i] = {fine.positions[i], normals[i]};
        fine_vertices.emplace();
        sim::Vec4Array rest(body.particle_count());
        for (size_t i = 0; i < rest.size(); ++i) rest[i] = sim::to4(body.rest_positions[i]);
        std::vector<Vec3f> rest_normals(rest.size());
        sim::update_normals(body.rings, rest, rest_normals, 0, rest.size());
        surface::embed_points(points, body.rest_positions, body.triangles, rest_normals, *fine_vertices);
    }
    surface::update_boundary_particles(body.triangles, body.particles.x, body.normals, *fine_vertices);
    const surface::BoundaryParticles& fv = *fine_vertices;
    x.resize(fv.size());
    for (size_t i = 0; i < fv.size(); ++i) x[i] = sim::to4(fv.position[i]);
    // The body keeps every particle's piece through its edits: a triangle's is its corners'.
    const auto piece = [&](uint32_t triangle) { return body.piece_of_particle[body.triangles[triangle][0]]; };
    // Two body triangles that met at rest (a corner at the same rest position) but share no
    // vertex now were torn or cut apart between them: a fine triangle with corners on both would
    // bridge the opening (a tear that has not yet split the piece leaves both in one component).
    const auto torn_apart = [&](uint32_t a, uint32_t b) {
        if (a == b) return false;
        const mesh::Triangle &ta = body.triangles[a], &tb = body.triangles[b];
        bool met = false;
        for (uint32_t i : ta)
            for (uint32_t j : tb) {
                if (i == j) return false;
                met = met || body.rest_positions[i] == body.rest_positions[j];
            }
        return met;
    };
    triangles.clear();
    for (const mesh::Triangle& t : fine.triangles) {
        const uint32_t e0 = fv.triangle[t[0]], e1 = fv.triangle[t[1]], e2 = fv.triangle[t[2]];
        const uint32_t c = piece(e0);
        if (piece(e1) != c || piece(e2) != c) continue;
        if (torn_apart(e0, e1) || torn_apart(e1, e2) || torn_apart(e0, e2)) continue;
        bool torn = false;
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = t[k], b = t[(k + 1) % 3];
            const float rest = (fine.positions[a] - fine.positions[b]).norm();
            torn = torn || (x[a] - x[b]).norm() > 3.0f * rest + 1e-6f;
        }
        if (!torn) triangles.push_back(t);
    }
}

} // namespace pbdsplat::scene
