#include "scene/stages/fine_surface.h"

#include <algorithm>

#include "mesh/decimate.h"
#include "mesh/topology.h"
#include "sim/integrate.h"
#include "surface/embedding.h"

namespace pbdsplat::scene {

namespace {

// Per edge k (from corner k) of `t`, the square of 3x its rest length: stretched past it, the
// edge was torn across by the body under it.
std::array<float, 3> tear_lengths2(const mesh::TriangleMesh& fine, const mesh::Triangle& t) {
    std::array<float, 3> r{};
    for (int k = 0; k < 3; ++k) r[size_t(k)] = 9.0f * (fine.positions[t[size_t(k)]] - fine.positions[t[size_t((k + 1) % 3)]]).squaredNorm();
    return r;
}

// Simplifies the whole triangles once the topology has held (FineTriangles::simplify_error).
void simplify_whole(const mesh::TriangleMesh& fine, bool changed, FineTriangles& f) {
    if (!(f.simplify_error > 0.0f)) return;
    if (changed) f.frames_held = 0, f.simplified_current = false;
    else if (f.frames_held < UINT32_MAX) ++f.frames_held;
    if (f.simplified_current || f.frames_held < f.settle_frames) return;
    f.simplified = mesh::simplify_triangles(fine.positions, f.whole, f.simplify_error);
    f.simplified_rest2.resize(f.simplified.size());
    for (size_t k = 0; k < f.simplified.size(); ++k) f.simplified_rest2[k] = tear_lengths2(fine, f.simplified[k]);
    f.simplified_current = true;
}

// The fine triangles whose corners lie on one piece, on body triangles not torn apart between
// them: two body triangles that met at rest (a corner at the same rest position) but share no
// vertex now were torn or cut apart there, and a fine triangle with corners on both would bridge
// the opening (a tear that has not yet split the piece leaves both in one component).
void judge_whole(const sim::SoftBody& body, const mesh::TriangleMesh& fine, const FineCopies& copies, const surface::BoundaryParticles& fv,
                 FineTriangles& out) {
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
    for (uint32_t k = 0; k < fine.triangles.size(); ++k) {
        if (copies.copied(k)) continue;
        const mesh::Triangle& t = fine.triangles[k];
        const uint32_t e0 = fv.triangle[t[0]], e1 = fv.triangle[t[1]], e2 = fv.triangle[t[2]];
        const uint32_t c = piece(e0);
        if (piece(e1) != c || piece(e2) != c) continue;
        if (torn_apart(e0, e1) || torn_apart(e1, e2) || torn_apart(e0, e2)) continue;
        out.whole.push_back(t);
        out.rest2.push_back(tear_lengths2(fine, t));
    }
    out.body_triangles = body.triangles.size(), out.particles = body.particle_count(), out.pieces = body.pieces;
}

// The body's triangles of the copied models, their corners at `base` + particle in `x`.
void append_copied(const sim::SoftBody& body, const FineCopies& copies, std::vector<Vec4f>& x, std::vector<mesh::Triangle>& triangles) {
    const uint32_t base = uint32_t(x.size());
    x.insert(x.end(), body.particles.x.begin(), body.particles.x.end());
    const bool models = body.model_of_particle.size() == body.particle_count();
    for (const mesh::Triangle& t : body.triangles) {
        const uint32_t m = models ? body.model_of_particle[t[0]] : 0u;
        if (m < copies.model.size() && copies.model[m]) triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    }
}

} // namespace

void mark_vertex_models(const sim::SoftBody& body, const surface::BoundaryParticles* fine_vertices, std::span<Vec4f> x) {
    if (body.model_count() < 2) return;
    const std::vector<uint32_t>& model = body.model_of_particle;
    const size_t fine = fine_vertices ? std::min(fine_vertices->size(), x.size()) : 0;
    for (size_t i = 0; i < fine; ++i) x[i].w() = float(model[body.triangles[fine_vertices->triangle[i]][0]]);
    for (size_t i = fine; i < x.size() && i - fine < model.size(); ++i) x[i].w() = float(model[i - fine]);
}

std::vector<Vec4f> particles_with_models(const sim::SoftBody& body) {
    std::vector<Vec4f> x(body.particles.x.begin(), body.particles.x.end());
    mark_vertex_models(body, nullptr, x);
    return x;
}

bool FineCopies::copied(uint32_t fine_triangle) const {
    for (const auto& [first, last] : triangles)
        if (fine_triangle >= first && fine_triangle < last) return true;
    return false;
}

void deformed_fine_surface(const sim::SoftBody& body, const mesh::TriangleMesh& fine, const FineCopies& copies,
                           std::optional<surface::BoundaryParticles>& fine_vertices, std::vector<Vec4f>& x,
                           std::vector<mesh::Triangle>& triangles, FineTriangles* keep) {
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
    const bool changed =
        judged.body_triangles != body.triangles.size() || judged.particles != body.particle_count() || judged.pieces != body.pieces;
    if (changed) judge_whole(body, fine, copies, fv, judged);
    simplify_whole(fine, changed, judged);
    const bool simple = judged.simplified_current;
    const std::vector<mesh::Triangle>& drawn = simple ? judged.simplified : judged.whole;
    const std::vector<std::array<float, 3>>& rest2 = simple ? judged.simplified_rest2 : judged.rest2;
    // An edge stretched past 3x its rest length was torn across by the body under it.
    triangles.clear();
    for (size_t k = 0; k < drawn.size(); ++k) {
        const mesh::Triangle& t = drawn[k];
        bool torn = false;
        for (int e = 0; e < 3; ++e)
            torn = torn || (x[t[size_t(e)]] - x[t[size_t((e + 1) % 3)]]).squaredNorm() > rest2[k][size_t(e)] + 1e-12f;
        if (!torn) triangles.push_back(t);
    }
    if (copies.any()) append_copied(body, copies, x, triangles);
}

} // namespace pbdsplat::scene
