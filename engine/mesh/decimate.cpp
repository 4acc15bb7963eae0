#include "mesh/decimate.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <optional>
#include <unordered_map>

namespace pbdsplat::mesh {

namespace {
// One simplification to about `target` vertices, compacted and repaired.
core::Result<RepairedMesh> simplify(const TriangleMesh& m, const std::vector<uint32_t>& indices, uint32_t target,
                                    bool lock_border, float& error, const std::string& name) {
    // A closed surface has about twice as many triangles as vertices (Euler); an open one a
    // little fewer, so the vertex target is the better-kept promise of the two.
    const size_t target_indices = size_t(target) * 2 * 3;
    std::vector<uint32_t> simplified(indices.size());
    const size_t count = meshopt_simplify(simplified.data(), indices.data(), indices.size(), m.positions[0].data(),
                                          m.positions.size(), sizeof(Vec3f), target_indices, 1.0f,
                                          lock_border ? unsigned(meshopt_SimplifyLockBorder) : 0u, &error);
    simplified.resize(count);
    if (count < 12) return core::make_error(name + ": decimation left fewer than 4 triangles; ask for more particles");
    // Keep the vertices the simplified triangles use, in order of first use.
    std::vector<uint32_t> remap(m.positions.size(), UINT32_MAX);
    TriangleMesh coarse;
    const bool colors = m.colors.size() == m.positions.size();
    for (uint32_t& v : simplified) {
        if (remap[v] == UINT32_MAX) {
            remap[v] = uint32_t(coarse.positions.size());
            coarse.positions.push_back(m.positions[v]);
            if (colors) coarse.colors.push_back(m.colors[v]);
        }
        v = remap[v];
    }
    for (size_t i = 0; i < simplified.size(); i += 3) coarse.triangles.push_back({simplified[i], simplified[i + 1], simplified[i + 2]});
    // No welding: the positions are the model's own, and distinct.
    RepairOptions ro;
    ro.weld_tolerance = 0.0f;
    return repair(std::move(coarse), ro, name + " (decimated)");
}
// Every directed edge at most once: what the topology stage and the volume need.
bool oriented_manifold(const TriangleMesh& m) {
    std::vector<uint64_t> edges;
    edges.reserve(m.triangles.size() * 3);
    for (const Triangle& t : m.triangles)
        for (int k = 0; k < 3; ++k) edges.push_back((uint64_t(t[k]) << 32) | t[(k + 1) % 3]);
    std::sort(edges.begin(), edges.end());
    return std::adjacent_find(edges.begin(), edges.end()) == edges.end();
}
} // namespace

core::Result<DecimatedMesh> decimate(const TriangleMesh& m, const DecimateOptions& o, const std::string& name) {
    DecimatedMesh out;
    out.report.input_vertices = m.vertex_count();
    out.report.input_triangles = m.triangle_count();
    if (o.target_vertices < 4)
        return core::make_error(name + ": a simulation mesh needs at least 4 particles (asked for " +
                                std::to_string(o.target_vertices) + ")");
    if (o.target_vertices >= m.vertex_count()) {
        out.mesh = m;
        out.report.output_vertices = m.vertex_count();
        out.report.output_triangles = m.triangle_count();
        return out;
    }
    std::vector<uint32_t> indices;
    indices.reserve(m.triangles.size() * 3);
    for (const Triangle& t : m.triangles) indices.insert(indices.end(), t.begin(), t.end());
    const size_t input_boundary = boundary_edge_count(m);
    // meshopt_simplify can leave a collapsed sliver (three collinear corners) or pinch a thin
    // part into a non-manifold edge; the repair would drop them and open holes. A slightly
    // different target takes other collapses: the first clean result wins.
    const float tries[] = {1.0f, 1.04f, 0.96f, 1.08f, 0.92f, 1.15f, 0.85f, 1.25f};
    std::optional<RepairedMesh> best;
    size_t best_score = SIZE_MAX;
    float error = 0.0f;
    for (float f : tries) {
        float e = 0.0f;
        auto attempt = simplify(m, indices, uint32_t(float(o.target_vertices) * f), o.lock_border, e, name);
        if (!attempt.ok()) return attempt.error();
        const RepairReport& r = attempt.value().report;
        // Holes the decimation opened, with a fold (a directed edge used twice) worst of all.
        const size_t score = (oriented_manifold(attempt.value().mesh) ? 0 : 1000000) +
                             (r.boundary_edges > input_boundary ? r.boundary_edges - input_boundary : 0) +
                             r.degenerate_triangles + r.duplicate_triangles + r.nonmanifold_edges + r.split_vertices;
        if (score < best_score) best = std::move(attempt.value()), best_score = score, error = e;
        if (score == 0) break;
    }
    // Still folded: drop the triangles on each doubled directed edge (a sliver folded over its
    // neighbour) and repair again; the hole is a few triangles wide and the volume caps it.
    for (int pass = 0; pass < 4 && !oriented_manifold(best->mesh); ++pass) {
        std::unordered_map<uint64_t, uint32_t> first;
        std::vector<uint8_t> drop(best->mesh.triangles.size(), 0);
        for (uint32_t t = 0; t < best->mesh.triangles.size(); ++t)
            for (int k = 0; k < 3; ++k) {
                const auto& tri = best->mesh.triangles[t];
                const auto [it, fresh] = first.emplace((uint64_t(tri[k]) << 32) | tri[(k + 1) % 3], t);
                if (!fresh) drop[t] = drop[it->second] = 1;
            }
        TriangleMesh kept;
        kept.positions = best->mesh.positions;
        kept.colors = best->mesh.colors;
        for (uint32_t t = 0; t < best->mesh.triangles.size(); ++t)
            if (!drop[t]) kept.triangles.push_back(best->mesh.triangles[t]);
        RepairOptions ro;
        ro.weld_tolerance = 0.0f;
        auto again = repair(std::move(kept), ro, name + " (decimated)");
        if (!again.ok()) return again.error();
        best = std::move(again.value());
    }
    if (!oriented_manifold(best->mesh))
        return core::make_error(name + ": the decimated mesh folds over itself; try another simulation.particles");
    out.mesh = std::move(best->mesh);
    out.report.repair = best->report;
    out.report.output_vertices = out.mesh.vertex_count();
    out.report.output_triangles = out.mesh.triangle_count();
    out.report.relative_error = error;
    return out;
}

} // namespace pbdsplat::mesh
