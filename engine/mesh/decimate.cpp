#include "mesh/decimate.h"

#include <meshoptimizer.h>

#include <algorithm>

namespace pbdsplat::mesh {

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
    // A closed surface has about twice as many triangles as vertices (Euler); an open one a
    // little fewer, so the vertex target is the better-kept promise of the two.
    const size_t target_indices = size_t(o.target_vertices) * 2 * 3;
    std::vector<uint32_t> simplified(indices.size());
    float error = 0.0f;
    const size_t count = meshopt_simplify(simplified.data(), indices.data(), indices.size(), m.positions[0].data(),
                                          m.positions.size(), sizeof(Vec3f), target_indices, 1.0f,
                                          o.lock_border ? unsigned(meshopt_SimplifyLockBorder) : 0u, &error);
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
    for (size_t i = 0; i < simplified.size(); i += 3)
        coarse.triangles.push_back({simplified[i], simplified[i + 1], simplified[i + 2]});

    // Collapses can pinch a thin part into a non-manifold edge or a degenerate triangle: the
    // repair the loader runs makes the result usable by the solver again. No welding: the
    // positions are the model's own, and distinct.
    RepairOptions ro;
    ro.weld_tolerance = 0.0f;
    auto repaired = repair(std::move(coarse), ro, name + " (decimated)");
    if (!repaired.ok()) return repaired.error();
    out.mesh = std::move(repaired.value().mesh);
    out.report.repair = repaired.value().report;
    out.report.output_vertices = out.mesh.vertex_count();
    out.report.output_triangles = out.mesh.triangle_count();
    out.report.relative_error = error;
    return out;
}

} // namespace pbdsplat::mesh
