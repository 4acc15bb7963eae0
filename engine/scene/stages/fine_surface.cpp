#include "scene/stages/fine_surface.h"

#include "mesh/topology.h"
#include "sim/integrate.h"
#include "surface/embedding.h"

namespace pbdsplat::scene {

namespace {

// The fine triangles whose corners lie on one piece, on body triangles not torn apart between
// them: two body triangles that met at rest (a corner at the same rest position) but share no
// vertex now were torn or cut apart there, and a fine triangle with corners on both would bridge
// the opening (a tear that has not yet split the piece leaves both in one component).
void judge_whole(const sim::SoftBody& body, const mesh::TriangleMesh& fine, const surface::BoundaryParticles& fv, FineTriangles& out) {
    const auto piece = [&](uint32_t triangle) { return body.piece_of_particle[body.triangles[triangle][0]]; };
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
    out.whole.clear(), out.rest2.clear();
    for (const mesh::Triangle& t : fine.triangles) {
        const uint32_t e0 = fv.triangle[t[0]], e1 = fv.triangle[t[1]], e2 = fv.triangle[t[2]];
        const uint32_t c = piece(e0);
        if (piece(e1) != c || piece(e2) != c) continue;
        if (torn_apart(e0, e1) || torn_apart(e1, e2) || torn_apart(e0, e2)) continue;
        std::array<float, 3> r{};
        for (int k = 0; k < 3; ++k) r[size_t(k)] = 9.0f * (fine.positions[t[k]] - fine.positions[t[(k + 1) % 3]]).squaredNorm();
        out.whole.push_back(t);
        out.rest2.push_back(r);
    }
    out.body_triangles = body.triangles.size(), out.particles = body.particle_count(), out.pieces = body.pieces;
}

} // namespace

void deformed_fine_surface(const sim::SoftBody& body, const mesh::TriangleMesh& fine, std::optional<surface::BoundaryParticles>& fine_vertices,
                           std::vector<Vec4f>& x, std::vector<mesh::Triangle>& triangles, FineTriangles* keep) {
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
        if (keep) keep->body_triangles = SIZE_MAX;  // judged against another embedding
    }
    surface::update_boundary_positions(body.triangles, body.particles.x, body.normals, *fine_vertices);
    const surface::BoundaryParticles& fv = *fine_vertices;
    x.resize(fv.size());
    for (size_t i = 0; i < fv.size(); ++i) x[i] = sim::to4(fv.position[i]);
    // Every edit changes the particle or triangle count (a cut adds both, a tear's split adds
    // particles), and only an edit changes which triangles are whole.
    FineTriangles local;
    FineTriangles& judged = keep ? *keep : local;
    if (judged.body_triangles != body.triangles.size() || judged.particles != body.particle_count() || judged.pieces != body.pieces)
        judge_whole(body, fine, fv, judged);
    // An edge stretched past 3x its rest length was torn across by the body under it.
    triangles.clear();
    for (size_t k = 0; k < judged.whole.size(); ++k) {
        const mesh::Triangle& t = judged.whole[k];
        bool torn = false;
        for (int e = 0; e < 3; ++e)
            torn = torn || (x[t[size_t(e)]] - x[t[size_t((e + 1) % 3)]]).squaredNorm() > judged.rest2[k][size_t(e)] + 1e-12f;
        if (!torn) triangles.push_back(t);
    }
}

} // namespace pbdsplat::scene
