#include "topology/invariants.h"

#include <cstdio>

#include <algorithm>
#include <numeric>
#include <string>
#include <unordered_map>
#include <unordered_set>

#include "mesh/topology.h"
#include "topology/edit.h"

namespace pbdsplat::topology {

namespace {
core::Status broken(const std::string& what) { return core::make_error("topology invariant broken: " + what); }
} // namespace

namespace {
core::Status check_particles(const sim::SoftBody& b) {
    const size_t n = b.particle_count();
    if (b.particles.x_prev.size() != n || b.particles.v.size() != n || b.particles.w.size() != n ||
        b.rest_positions.size() != n || b.normals.size() != n || (!b.colors.empty() && b.colors.size() != n) ||
        (!b.texcoords.empty() && b.texcoords.size() != n))
        return broken("the per-particle arrays differ in length");
    for (size_t i = 0; i < n; ++i)
        if (!b.particles.x[i].allFinite() || !b.particles.v[i].allFinite() || !std::isfinite(b.particles.w[i]) ||
            b.particles.w[i] < 0.0f)
            return broken("particle " + std::to_string(i) + " has a non-finite state or a negative inverse mass");
    return core::Status::success();
}
// Every volume constraint over live particles of a single component, with a positive target,
// in increasing piece order, and no particle twice on the cap loops (the solver's cap terms count each loop particle once).
core::Status check_volumes(const sim::SoftBody& b) {
    std::vector<uint8_t> kept(b.pieces, 0), on_loop(b.particle_count(), 0);
    for (size_t k = 0; k < b.volumes.size(); ++k) {
        const auto& vol = b.volumes[k];
        if (vol.piece >= b.pieces) return broken("volume constraint " + std::to_string(k) + " names a piece the body does not have");
        if (kept[vol.piece]++) return broken("two volume constraints keep piece " + std::to_string(vol.piece));
        // In piece order, so a cut finds the constraints of the pieces it reached by bisection.
        if (k > 0 && b.volumes[k - 1].piece > vol.piece)
            return broken("volume constraints out of piece order at " + std::to_string(k) + " (piece " + std::to_string(vol.piece) + " after " +
                          std::to_string(b.volumes[k - 1].piece) + ")");
        if (!vol.cap_bounds.empty() && vol.cap_bounds.size() != vol.cap_loops.size())
            return broken("volume constraint " + std::to_string(k) + " has rest bounds for some of its cap loops only");
        for (size_t l = 0; l < vol.cap_bounds.size(); ++l)
            for (uint32_t i : vol.cap_loops[l])
                if (i < b.particle_count() &&
                    (b.rest_positions[i] - vol.cap_bounds[l].head<3>()).norm() > vol.cap_bounds[l].w() * 1.0001f + 1e-6f)
                    return broken("volume constraint " + std::to_string(k) + "'s cap loop " + std::to_string(l) +
                                  " leaves its rest bounds (the cut would miss that it reached it)");
        for (const auto& loop : vol.cap_loops)
            for (uint32_t i : loop)
                if (i >= b.particle_count() || b.piece_of_particle[i] != vol.piece)
                    return broken("volume constraint " + std::to_string(k) + "'s cap loop leaves its piece");
                else if (on_loop[i]++)
                    return broken("particle " + std::to_string(i) + " lies twice on volume constraint " + std::to_string(k) +
                                  "'s cap loops (a bow-tie vertex the cut left unsplit)");
        if (!(vol.rest_volume > 0.0) || !std::isfinite(vol.rest_volume)) return broken("a volume constraint has no positive rest volume");
    }
    return core::Status::success();
}
} // namespace

namespace {

// Corners that exist and differ, and no sliver (rest area under min_area_ratio of the mean).
core::Status check_triangles(const sim::SoftBody& b, const InvariantOptions& o) {
    const size_t n = b.particle_count();
    const auto rest_area = [&](const mesh::Triangle& t) {
        return 0.5 * double((b.rest_positions[t[1]] - b.rest_positions[t[0]]).cross(b.rest_positions[t[2]] - b.rest_positions[t[0]]).norm());
    };
    double mean_area = 0.0;
    for (const auto& t : b.triangles) {
        for (uint32_t v : t)
            if (v >= n) return broken("a triangle refers to particle " + std::to_string(v) + " of " + std::to_string(n));
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) return broken("a triangle repeats a corner");
        mean_area += rest_area(t);
    }
    mean_area /= double(std::max<size_t>(1, b.triangles.size()));
    for (size_t f = 0; f < b.triangles.size(); ++f) {
        const double a = rest_area(b.triangles[f]);
        if (a < double(o.min_area_ratio) * mean_area) {
            char buf[160];
            std::snprintf(buf, sizeof(buf), "triangle %zu is a sliver (rest area %.3g, %.3g of the mean %.3g)", f, a, a / mean_area, mean_area);
            return broken(buf);
        }
    }
    return core::Status::success();
}

// One fan per vertex: around v, the triangles joined through shared edges form one group.
core::Status check_fans(const sim::SoftBody& b) {
    const size_t n = b.particle_count();
    std::vector<uint32_t> start(n + 1, 0), ring(b.triangles.size() * 3);
    for (const auto& t : b.triangles)
        for (uint32_t v : t) ++start[v + 1];
    for (size_t v = 0; v < n; ++v) start[v + 1] += start[v];
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    for (uint32_t f = 0; f < b.triangles.size(); ++f)
        for (uint32_t v : b.triangles[f]) ring[fill[v]++] = f;
    std::vector<uint32_t> root;
    for (uint32_t v = 0; v < n; ++v) {
        const uint32_t m = start[v + 1] - start[v];
        if (m < 2) continue;
        root.resize(m);
        std::iota(root.begin(), root.end(), 0u);
        auto find = [&](uint32_t x) {
            while (root[x] != x) x = root[x] = root[root[x]];
            return x;
        };
        uint32_t groups = m;
        for (uint32_t a = 0; a < m; ++a)
            for (uint32_t c = a + 1; c < m; ++c) {
                const auto& ta = b.triangles[ring[start[v] + a]];
                const auto& tc = b.triangles[ring[start[v] + c]];
                for (uint32_t w : ta)
                    if (w != v && std::find(tc.begin(), tc.end(), w) != tc.end() && find(a) != find(c)) {
                        root[find(a)] = find(c);
                        --groups;
                    }
            }
        if (groups != 1) return broken("vertex " + std::to_string(v) + " is a bow-tie (" + std::to_string(groups) + " fans)");
    }
    return core::Status::success();
}

} // namespace

core::Status check_invariants(const sim::SoftBody& b, const InvariantOptions& o) {
    const size_t n = b.particle_count();
    PBDSPLAT_TRY(check_particles(b));
    PBDSPLAT_TRY(check_triangles(b, o));
    // Orientation and manifoldness from the directed edges.
    std::unordered_set<uint64_t> directed;
    directed.reserve(b.triangles.size() * 3);
    for (const auto& t : b.triangles)
        for (int k = 0; k < 3; ++k)
            if (!directed.insert((uint64_t(t[size_t(k)]) << 32) | t[size_t((k + 1) % 3)]).second)
                return broken("edge " + std::to_string(t[size_t(k)]) + "-" + std::to_string(t[size_t((k + 1) % 3)]) +
                              " is used twice in one direction (orientation or manifoldness broken)");
    PBDSPLAT_TRY(check_fans(b));
    for (const auto& c : b.distance) {
        if (!c.alive()) continue;  // a slot emptied by an edit
        if (c.i >= n || c.j >= n || c.i == c.j) return broken("a distance constraint refers to a missing particle");
        if (!directed.count((uint64_t(c.i) << 32) | c.j) && !directed.count((uint64_t(c.j) << 32) | c.i))
            return broken("distance constraint " + std::to_string(c.i) + "-" + std::to_string(c.j) + " is not on a surface edge");
        if (!(c.rest >= 0.0f) || !std::isfinite(c.rest)) return broken("a distance constraint has a bad rest length");
    }
    PBDSPLAT_TRY(check_volumes(b));
    return check_derived(b);
}

core::Status check_derived(const sim::SoftBody& b) {
    const size_t n = b.particle_count();
    const sim::VertexRings fresh = sim::build_vertex_rings(b.triangles, n);
    if (!(fresh.ring == b.rings.ring) || !(fresh.triangles == b.rings.triangles))
        return broken("the vertex rings differ from a full build");
    if (!sim::distance_groups_valid(b.distance, b.distance_groups, n)) return broken("the distance colour groups are not valid");
    if (b.distance_lambda.size() != b.distance.size()) return broken("the XPBD multipliers do not match the constraints");
    // The piece labels: one per component, whatever the numbering.
    std::vector<uint32_t> fresh_label;
    if (sim::label_pieces(b.triangles, n, fresh_label) != b.pieces) return broken("the piece count differs from a component count");
    if (b.piece_of_particle.size() != n) return broken("the piece labels do not cover the particles");
    std::vector<uint32_t> kept_of_fresh(b.pieces, UINT32_MAX), fresh_of_kept(b.pieces, UINT32_MAX);
    for (size_t i = 0; i < n; ++i) {
        const uint32_t f = fresh_label[i], k = b.piece_of_particle[i];
        if (f == sim::k_no_piece || k >= b.pieces) {
            if (f != k) return broken("particle " + std::to_string(i) + "'s piece label differs from a fresh labelling");
            continue;
        }
        if (kept_of_fresh[f] == UINT32_MAX) kept_of_fresh[f] = k;
        if (fresh_of_kept[k] == UINT32_MAX) fresh_of_kept[k] = f;
        if (kept_of_fresh[f] != k || fresh_of_kept[k] != f)
            return broken("particle " + std::to_string(i) + "'s piece label differs from a fresh labelling");
    }
    // Loops compared as cycles (each turned to start at its lowest vertex), direction included:
    // a reversed cap adds the volume it should remove.
    auto canonical = [](std::vector<uint32_t> loop) {
        std::rotate(loop.begin(), std::min_element(loop.begin(), loop.end()), loop.end());
        return loop;
    };
    std::vector<std::vector<std::vector<uint32_t>>> loops_of_piece(b.pieces);
    for (const auto& loop : mesh::boundary_loops(b.triangles, n)) loops_of_piece[b.piece_of_particle[loop[0]]].push_back(canonical(loop));
    for (auto& loops : loops_of_piece) std::sort(loops.begin(), loops.end());
    std::vector<size_t> triangles_of_piece(b.pieces, 0);
    for (const auto& t : b.triangles) ++triangles_of_piece[b.piece_of_particle[t[0]]];
    for (size_t k = 0; k < b.volumes.size(); ++k) {
        const sim::VolumeConstraint& v = b.volumes[k];
        if (triangles_of_piece[v.piece] != v.triangle_count)
            return broken("volume constraint " + std::to_string(k) + "'s triangle count differs from its piece's");
        std::vector<std::vector<uint32_t>> caps;
        for (const auto& loop : v.cap_loops) caps.push_back(canonical(loop));
        std::sort(caps.begin(), caps.end());
        if (caps != loops_of_piece[v.piece])
            return broken("volume constraint " + std::to_string(k) + "'s cap loops differ from its piece's boundary loops");
    }
    return core::Status::success();
}

MeshCounts count_components_and_loops(const sim::SoftBody& b) {
    std::vector<uint32_t> comp;
    MeshCounts c;
    c.components = mesh::vertex_components(b.triangles, b.particle_count(), comp);
    c.boundary_loops = mesh::boundary_loops(b.triangles, b.particle_count()).size();
    return c;
}

} // namespace pbdsplat::topology
