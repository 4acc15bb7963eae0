#include "topology/separate.h"

#include <algorithm>
#include <unordered_map>

#include "core/timer.h"
#include "mesh/topology.h"
#include "sim/volume.h"

namespace pbdsplat::topology {

core::Result<TopologyChange> separate(sim::SoftBody& b, const std::function<bool(uint32_t)>& side,
                                      const std::function<bool(uint32_t)>& splittable) {
    const core::Stopwatch clock;
    TopologyChange change;
    const size_t n = b.particle_count();
    {
        std::vector<uint32_t> comp;
        change.components_before = mesh::triangle_components(mesh::TriangleMesh{b.rest_positions, b.triangles, {}, {}, {}}, comp);
    }
    // Which sides use each vertex.
    std::vector<uint8_t> sides(n, 0);
    std::vector<bool> positive(b.triangles.size());
    for (uint32_t t = 0; t < b.triangles.size(); ++t) {
        positive[t] = side(t);
        for (uint32_t v : b.triangles[t]) sides[v] = uint8_t(sides[v] | (positive[t] ? 2u : 1u));
    }
    std::vector<uint32_t> copy_of(n, UINT32_MAX);
    for (uint32_t v = 0; v < n; ++v) {
        if (sides[v] != 3 || !splittable(v)) continue;
        const uint32_t c = uint32_t(b.particles.size());
        b.particles.x.push_back(b.particles.x[v]);
        b.particles.x_prev.push_back(b.particles.x_prev[v]);
        b.particles.v.push_back(b.particles.v[v]);
        b.particles.w[v] *= 2.0f;  // half the mass each: the total is kept (pins stay pinned)
        b.particles.w.push_back(b.particles.w[v]);
        b.rest_positions.push_back(b.rest_positions[v]);
        if (!b.colors.empty()) b.colors.push_back(b.colors[v]);
        b.normals.push_back(v < b.normals.size() ? b.normals[v] : Vec3f::UnitY());
        copy_of[v] = c;
        ++change.split_vertices;
    }
    if (change.split_vertices == 0) {
        change.ms = clock.elapsed_ms();
        return change;
    }
    for (uint32_t t = 0; t < b.triangles.size(); ++t) {
        if (!positive[t]) continue;
        bool touched = false;
        for (uint32_t& v : b.triangles[t])
            if (copy_of[v] != UINT32_MAX) v = copy_of[v], touched = true;
        change.touched_triangles += touched ? 1 : 0;
    }
    change.new_particles = change.split_vertices;

    // Distance constraints keep their definitions; only their indices move. An edge whose two
    // triangles now lie on different sides exists twice (once per side).
    std::unordered_map<uint64_t, bool> edge_on;  // (a,b) -> used by a triangle
    auto key = [](uint32_t a, uint32_t c) { return (uint64_t(std::min(a, c)) << 32) | std::max(a, c); };
    for (const auto& t : b.triangles)
        for (int k = 0; k < 3; ++k) edge_on[key(t[size_t(k)], t[size_t((k + 1) % 3)])] = true;
    std::vector<sim::DistanceConstraint> distance;
    distance.reserve(b.distance.size() + change.split_vertices * 2);
    for (const sim::DistanceConstraint& c : b.distance) {
        const uint32_t ends[2][2] = {{c.i, copy_of[c.i]}, {c.j, copy_of[c.j]}};
        for (uint32_t a : ends[0])
            for (uint32_t e : ends[1])
                if (a != UINT32_MAX && e != UINT32_MAX && edge_on.count(key(a, e))) distance.push_back({a, e, c.rest, c.compliance});
    }
    b.distance = std::move(distance);

    // One volume constraint per component, re-measured now that the body is open.
    const mesh::TriangleMesh m{b.rest_positions, b.triangles, {}, {}, {}};
    if (!b.volumes.empty()) {
        const float pressure = b.volumes[0].pressure;
        const float compliance = b.volumes[0].compliance;
        std::vector<uint32_t> comp;
        const uint32_t nc = mesh::triangle_components(m, comp);
        std::vector<sim::VolumeConstraint> volumes(nc);
        for (size_t f = 0; f < b.triangles.size(); ++f) volumes[comp[f]].triangles.push_back(b.triangles[f]);
        std::vector<uint32_t> comp_of_vertex(b.particle_count(), UINT32_MAX);
        for (size_t f = 0; f < b.triangles.size(); ++f)
            for (uint32_t v : b.triangles[f]) comp_of_vertex[v] = comp[f];
        for (auto& loop : mesh::boundary_loops(m)) volumes[comp_of_vertex[loop[0]]].cap_loops.push_back(std::move(loop));
        for (sim::VolumeConstraint& v : volumes) {
            v.pressure = 1.0f;
            v.compliance = compliance;
            v.rest_volume = sim::constraint_volume<float>(v, b.particles.x) / double(pressure);
            v.pressure = pressure;  // the target stays k * V0, at the volume each piece has now
        }
        std::erase_if(volumes, [](const sim::VolumeConstraint& v) { return !(v.rest_volume > 0.0); });
        b.volumes = std::move(volumes);
    }
    std::vector<uint32_t> comp;
    change.components_after = mesh::triangle_components(m, comp);
    sim::rebuild_derived(b);
    change.ms = clock.elapsed_ms();
    return change;
}

core::Status check_invariants(const sim::SoftBody& b) {
    const size_t n = b.particle_count();
    if (b.particles.x_prev.size() != n || b.particles.v.size() != n || b.particles.w.size() != n || b.rest_positions.size() != n)
        return core::make_error("topology: the particle arrays differ in length");
    for (const auto& t : b.triangles)
        for (uint32_t v : t)
            if (v >= n) return core::make_error("topology: a triangle refers to particle " + std::to_string(v) + " of " + std::to_string(n));
    for (const auto& c : b.distance)
        if (c.i >= n || c.j >= n || c.i == c.j) return core::make_error("topology: a distance constraint refers to a missing particle");
    // Manifold with boundary: every edge in at most two triangles, with opposite directions.
    std::unordered_map<uint64_t, int> directed;
    for (const auto& t : b.triangles)
        for (int k = 0; k < 3; ++k)
            if (++directed[(uint64_t(t[size_t(k)]) << 32) | t[size_t((k + 1) % 3)]] > 1)
                return core::make_error("topology: an edge is used twice in the same direction (orientation broken)");
    for (const auto& v : b.volumes)
        for (const auto& t : v.triangles)
            for (uint32_t i : t)
                if (i >= n) return core::make_error("topology: a volume constraint refers to a missing particle");
    return core::Status::success();
}

} // namespace pbdsplat::topology
