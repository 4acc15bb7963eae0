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
    // little fewer, so the vertex target is the better-kept promise of the two. Where that asks
    // for more triangles than the mesh has (an open sheet, a mesh of many loose parts: fewer
    // than two per vertex), the mesh's own ratio of triangles to vertices is kept instead.
    size_t target_indices = size_t(target) * 2 * 3;
    if (target_indices > indices.size())
        target_indices = std::min(indices.size(), indices.size() * size_t(target) / std::max<size_t>(m.positions.size(), 1));
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
// Triangles under 1/1000 of the mean area: the topology stage rejects them (a sliver's normal
// and its splats' shading are noise), and a cut through one makes worse.
size_t slivers(const TriangleMesh& m) {
    std::vector<float> area(m.triangles.size());
    double mean = 0.0;
    for (size_t t = 0; t < area.size(); ++t) {
        const auto& tri = m.triangles[t];
        area[t] = 0.5f * (m.positions[tri[1]] - m.positions[tri[0]]).cross(m.positions[tri[2]] - m.positions[tri[0]]).norm();
        mean += double(area[t]);
    }
    mean /= double(std::max<size_t>(1, area.size()));
    return size_t(std::count_if(area.begin(), area.end(), [&](float a) { return double(a) < 1e-3 * mean; }));
}
// Flips the longest edge of each sliver: the flat triangle (a, b, c), c nearly on a-b, and its
// neighbour (b, a, d) become (a, d, c) and (d, b, c). An edge flip changes no vertex, keeps the
// surface closed and oriented, and is taken only when both new triangles are larger than the
// sliver and face the way the pair did. Returns how many were flipped.
size_t flip_slivers(TriangleMesh& m) {
    auto area = [&](const Triangle& t) {
        return 0.5f * (m.positions[t[1]] - m.positions[t[0]]).cross(m.positions[t[2]] - m.positions[t[0]]).norm();
    };
    auto normal = [&](const Triangle& t) {
        return Vec3f((m.positions[t[1]] - m.positions[t[0]]).cross(m.positions[t[2]] - m.positions[t[0]]));
    };
    double mean = 0.0;
    for (const Triangle& t : m.triangles) mean += double(area(t));
    mean /= double(std::max<size_t>(1, m.triangles.size()));
    auto key = [](uint32_t a, uint32_t b) { return (uint64_t(a) << 32) | b; };
    std::unordered_map<uint64_t, uint32_t> directed;  // directed edge -> its triangle
    for (uint32_t t = 0; t < m.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) directed[key(m.triangles[t][k], m.triangles[t][(k + 1) % 3])] = t;
    size_t flipped = 0;
    for (uint32_t t = 0; t < m.triangles.size(); ++t) {
        const Triangle s = m.triangles[t];
        if (double(area(s)) >= 1e-3 * mean) continue;
        int longest = 0;
        float best = -1.0f;
        for (int k = 0; k < 3; ++k) {
            const float len = (m.positions[s[(k + 1) % 3]] - m.positions[s[k]]).squaredNorm();
            if (len > best) best = len, longest = k;
        }
        const uint32_t a = s[longest], b = s[(longest + 1) % 3], c = s[(longest + 2) % 3];
        const auto other = directed.find(key(b, a));
        if (other == directed.end()) continue;  // a border edge: nothing to flip with
        const uint32_t u = other->second;
        const Triangle& n = m.triangles[u];
        uint32_t d = n[0] + n[1] + n[2] - a - b;
        if (d == c || directed.count(key(c, d)) || directed.count(key(d, c))) continue;  // would double an edge
        const Triangle t1{a, d, c}, t2{d, b, c};
        const Vec3f before = normal(s) + normal(n);
        if (!(area(t1) > area(s) && area(t2) > area(s)) || normal(t1).dot(before) <= 0.0f || normal(t2).dot(before) <= 0.0f)
            continue;
        for (const Triangle& old : {s, n})
            for (int k = 0; k < 3; ++k) directed.erase(key(old[k], old[(k + 1) % 3]));
        m.triangles[t] = t1;
        m.triangles[u] = t2;
        for (uint32_t q : {t, u})
            for (int k = 0; k < 3; ++k) directed[key(m.triangles[q][k], m.triangles[q][(k + 1) % 3])] = q;
        ++flipped;
    }
    return flipped;
}
// The mesh without the triangles on a directed edge used twice (both of them).
TriangleMesh without_folds(const TriangleMesh& m) {
    std::unordered_map<uint64_t, uint32_t> first;
    std::vector<uint8_t> drop(m.triangles.size(), 0);
    for (uint32_t t = 0; t < m.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) {
            const auto& tri = m.triangles[t];
            const auto [it, fresh] = first.emplace((uint64_t(tri[k]) << 32) | tri[(k + 1) % 3], t);
            if (!fresh) drop[t] = drop[it->second] = 1;
        }
    TriangleMesh kept;
    kept.positions = m.positions;
    kept.colors = m.colors;
    for (uint32_t t = 0; t < m.triangles.size(); ++t)
        if (!drop[t]) kept.triangles.push_back(m.triangles[t]);
    return kept;
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
    // meshopt_simplify can leave a collapsed sliver (three collinear corners, or nearly), or
    // pinch a thin part into a non-manifold edge; the repair would drop them and open holes. A
    // slightly different target takes other collapses: the first clean result wins.
    const float tries[] = {1.0f, 1.04f, 0.96f, 1.08f, 0.92f, 1.15f, 0.85f, 1.25f};
    std::optional<RepairedMesh> best;
    size_t best_score = SIZE_MAX;
    float error = 0.0f;
    for (float f : tries) {
        float e = 0.0f;
        auto attempt = simplify(m, indices, uint32_t(float(o.target_vertices) * f), o.lock_border, e, name);
        if (!attempt.ok()) return attempt.error();
        // A flip can make a neighbour the next sliver's partner: a few passes settle it.
        for (int pass = 0; pass < 3; ++pass)
            if (flip_slivers(attempt.value().mesh) == 0) break;
        const RepairReport& r = attempt.value().report;
        // Holes the decimation opened, with a fold (a directed edge used twice) worst of all.
        const size_t score = (oriented_manifold(attempt.value().mesh) ? 0 : 1000000) +
                             (r.boundary_edges > input_boundary ? r.boundary_edges - input_boundary : 0) +
                             r.degenerate_triangles + r.duplicate_triangles + r.nonmanifold_edges + r.split_vertices +
                             100 * slivers(attempt.value().mesh);
        if (score < best_score) best = std::move(attempt.value()), best_score = score, error = e;
        if (score == 0) break;
    }
    // Still folded: drop the triangles on each doubled directed edge (a sliver folded over its
    // neighbour) and repair again; the hole is a few triangles wide and the volume caps it.
    for (int pass = 0; pass < 4 && !oriented_manifold(best->mesh); ++pass) {
        auto again = repair(without_folds(best->mesh), RepairOptions{.weld_tolerance = 0.0f}, name + " (decimated)");
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

std::vector<Triangle> simplify_triangles(std::span<const Vec3f> positions, std::span<const Triangle> triangles, float max_error) {
    std::vector<Triangle> out(triangles.begin(), triangles.end());
    if (triangles.empty() || positions.empty() || !(max_error > 0.0f)) return out;
    std::vector<uint32_t> indices;
    indices.reserve(triangles.size() * 3);
    Vec3f lo = positions[triangles[0][0]], hi = lo;
    for (const Triangle& t : triangles)
        for (uint32_t v : t) {
            if (v >= positions.size()) return out;  // not a mesh over these positions: left alone
            indices.push_back(v);
            lo = lo.cwiseMin(positions[v]), hi = hi.cwiseMax(positions[v]);
        }
    // meshoptimizer's error is relative to the mesh's extent; a target count of zero lets the
    // error alone say where to stop.
    const float extent = (hi - lo).maxCoeff();
    if (!(extent > 0.0f)) return out;
    std::vector<uint32_t> simplified(indices.size());
    const size_t count = meshopt_simplify(simplified.data(), indices.data(), indices.size(), positions[0].data(), positions.size(),
                                          sizeof(Vec3f), 0, max_error / extent, unsigned(meshopt_SimplifyLockBorder), nullptr);
    out.clear();
    for (size_t i = 0; i + 2 < count; i += 3) out.push_back({simplified[i], simplified[i + 1], simplified[i + 2]});
    return out;
}

} // namespace pbdsplat::mesh
