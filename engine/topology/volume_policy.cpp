#include "topology/volume_policy.h"

#include <cmath>


#include "mesh/topology.h"
#include "sim/volume.h"

namespace pbdsplat::topology {

namespace {
// A piece too thin or too small to hold air: a flake torn off a shell, a sliver of a few
// triangles. Its capped volume is nearly zero against its area, so a volume constraint on it
// has a tiny gradient and a projection step of C / |grad|^2 that flings its particles away: it
// gets none and moves as cloth. A sphere scores V / A^1.5 = 0.094, a shallow dome of height
// 0.05 r about 0.014.
bool holds_air(const sim::VolumeConstraint& v, double volume, const sim::Vec4Array& x) {
    if (v.triangles.size() < 12) return false;
    double area = 0.0;
    for (const auto& t : v.triangles)
        area += 0.5 * double((x[t[1]] - x[t[0]]).head<3>().cross((x[t[2]] - x[t[0]]).head<3>()).norm());
    return area > 0.0 && std::abs(volume) / std::pow(area, 1.5) >= 0.01;
}
} // namespace

namespace {
// Edge (a, b) of triangle t is on the boundary when no other triangle has both ends.
bool on_boundary(const sim::SoftBody& body, uint32_t t, uint32_t a, uint32_t b) {
    for (uint32_t f : body.rings.triangles.of(a))
        if (f != t && std::ranges::find(body.triangles[f], b) != body.triangles[f].end()) return false;
    return true;
}

// The boundary edge leaving v (in its triangle's direction), or UINT32_MAX. Without bow-ties
// (an invariant) a boundary vertex has exactly one.
uint32_t next_on_boundary(const sim::SoftBody& body, uint32_t v) {
    for (uint32_t f : body.rings.triangles.of(v)) {
        const mesh::Triangle& t = body.triangles[f];
        const int c = t[0] == v ? 0 : t[1] == v ? 1 : 2;
        const uint32_t w = t[size_t((c + 1) % 3)];
        if (on_boundary(body, f, v, w)) return w;
    }
    return UINT32_MAX;
}

// The boundary loops through the edited region, traced along the body's rings: from every
// boundary edge of the touched triangles and from every vertex of the old loops that passed
// through the region (their other edges did not change). Costs the loops' length, not the body's.
// Returns false where a trace does not close (then the caller counts the loops over all).
bool trace_loops(const sim::SoftBody& body, std::span<const uint32_t> touched_triangles,
                 std::span<const std::vector<uint32_t>* const> old_loops, std::vector<std::vector<uint32_t>>& loops) {
    std::vector<uint32_t> seeds;
    for (uint32_t f : touched_triangles) {
        const mesh::Triangle& t = body.triangles[f];
        for (int k = 0; k < 3; ++k)
            if (on_boundary(body, f, t[size_t(k)], t[size_t((k + 1) % 3)])) seeds.push_back(t[size_t(k)]);
    }
    for (const std::vector<uint32_t>* loop : old_loops) seeds.insert(seeds.end(), loop->begin(), loop->end());
    std::sort(seeds.begin(), seeds.end());
    seeds.erase(std::unique(seeds.begin(), seeds.end()), seeds.end());
    std::vector<uint8_t> on_loop(seeds.size(), 0);  // seeds met by a loop traced earlier
    const size_t limit = body.particle_count() + 1;
    for (size_t s = 0; s < seeds.size(); ++s) {
        if (on_loop[s]) continue;
        const uint32_t start = seeds[s];
        uint32_t next = next_on_boundary(body, start);
        if (next == UINT32_MAX) continue;  // an old loop's vertex that is now inside
        std::vector<uint32_t> loop{start};
        while (next != start) {
            if (next == UINT32_MAX || loop.size() > limit) return false;
            loop.push_back(next);
            next = next_on_boundary(body, next);
        }
        for (uint32_t v : loop)
            if (auto it = std::lower_bound(seeds.begin(), seeds.end(), v); it != seeds.end() && *it == v) on_loop[size_t(it - seeds.begin())] = 1;
        // Caps run against their triangles' boundary edges (mesh::boundary_loops' direction),
        // so a fan over the loop continues the surface outward.
        std::reverse(loop.begin(), loop.end());
        loops.push_back(std::move(loop));
    }
    return true;
}
// The cap loops of the remade pieces: loops of the touched constraints that kept clear of the
// edit stay as they were, the rest are traced locally. Returns false where the trace fell
// back to counting the loops over the remade pieces.
bool cap_remade_pieces(const sim::SoftBody& b, std::span<const uint32_t> comp, std::span<const uint8_t> remake,
                       std::span<const OldVolume> old, std::span<const uint8_t> touched, std::span<const uint32_t> touched_triangles,
                       std::span<const mesh::Triangle> remade_triangles, std::vector<sim::VolumeConstraint>& pieces) {
    std::vector<uint32_t> comp_of_vertex(b.particle_count(), UINT32_MAX);
    for (size_t t = 0; t < b.triangles.size(); ++t)
        if (remake[comp[t]])
            for (uint32_t v : b.triangles[t]) comp_of_vertex[v] = comp[t];
    std::vector<uint8_t> in_region(b.particle_count(), 0);
    for (uint32_t f : touched_triangles)
        for (uint32_t v : b.triangles[f]) in_region[v] = 1;
    std::vector<std::vector<uint32_t>> loops;
    std::vector<const std::vector<uint32_t>*> retrace;
    for (size_t k = 0; k < old.size(); ++k) {
        if (!touched[k]) continue;
        for (const std::vector<uint32_t>& loop : b.volumes[k].cap_loops) {
            const bool reached = std::any_of(loop.begin(), loop.end(), [&](uint32_t v) { return in_region[v] != 0; });
            if (reached) retrace.push_back(&loop);
            else loops.push_back(loop);
        }
    }
    const bool traced = trace_loops(b, touched_triangles, retrace, loops);
    if (!traced) loops = mesh::boundary_loops(remade_triangles, b.particle_count());
    for (auto& loop : loops)
        if (comp_of_vertex[loop[0]] != UINT32_MAX) pieces[comp_of_vertex[loop[0]]].cap_loops.push_back(std::move(loop));
    return traced;
}

// A remade piece's target volume by the policy, from its parent's.
void set_target(sim::VolumeConstraint& v, const OldVolume& parent, bool unchanged, double now, VolumePolicy policy, float leak) {
    v.pressure = parent.pressure;
    v.compliance = parent.compliance;
    v.leak = parent.leak;
    if (unchanged) {
        v.rest_volume = parent.rest_volume;
    } else if (policy == VolumePolicy::rebase) {
        v.rest_volume = now / double(v.pressure);  // the target is the volume it has now
    } else {
        v.rest_volume = parent.now > 0.0 ? parent.rest_volume * now / parent.now : 0.0;
        // Opened: the pressure escapes through the opening, over a few frames.
        if (policy == VolumePolicy::burst && !v.cap_loops.empty()) v.leak = std::max(v.leak, leak);
    }
}
} // namespace

VolumeOutcome apply_volume_policy(sim::SoftBody& b, VolumePolicy policy, float leak, std::span<const int32_t> old_of_triangle,
                                  std::span<OldVolume> old, std::span<const uint8_t> touched, std::span<const uint32_t> touched_triangles) {
    VolumeOutcome result;
    std::vector<uint32_t>& rebuilt = result.rebuilt;
    std::vector<uint32_t> comp;
    const uint32_t nc = mesh::vertex_components(b.triangles, b.particle_count(), comp);
    result.pieces = nc;
    if (old.empty()) return result;
    std::vector<int32_t> from(nc, -1);
    for (size_t t = 0; t < b.triangles.size(); ++t)
        if (from[comp[t]] < 0) from[comp[t]] = old_of_triangle[t];
    // The volume of each touched constraint just before the change: its triangles still name
    // the old corners, whose positions did not move.
    for (size_t k = 0; k < old.size(); ++k)
        if (touched[k]) old[k].now = sim::constraint_volume<float>(b.volumes[k], b.particles.x);
    std::vector<sim::VolumeConstraint> pieces(nc);
    std::vector<uint8_t> remake(nc, 0);
    std::vector<mesh::Triangle> remade_triangles;  // of all remade pieces, for their boundary loops
    for (uint32_t c = 0; c < nc; ++c) remake[c] = from[c] >= 0 && touched[size_t(from[c])];
    for (size_t t = 0; t < b.triangles.size(); ++t)
        if (remake[comp[t]]) pieces[comp[t]].triangles.push_back(b.triangles[t]), remade_triangles.push_back(b.triangles[t]);
    if (!remade_triangles.empty())
        result.loops_fell_back = !cap_remade_pieces(b, comp, remake, old, touched, touched_triangles, remade_triangles, pieces);

    std::vector<double> now(nc, 0.0);
    std::vector<uint32_t> pieces_of_old(old.size(), 0);
    for (uint32_t c = 0; c < nc; ++c) {
        if (from[c] < 0) continue;
        if (remake[c]) now[c] = sim::constraint_volume<float>(pieces[c], b.particles.x);
        ++pieces_of_old[size_t(from[c])];
    }
    std::vector<sim::VolumeConstraint> out;
    for (uint32_t c = 0; c < nc; ++c) {
        if (from[c] < 0) continue;
        if (!remake[c]) {  // a piece the change did not reach keeps its constraint as it was
            out.push_back(std::move(b.volumes[size_t(from[c])]));
            continue;
        }
        const OldVolume& parent = old[size_t(from[c])];
        sim::VolumeConstraint& v = pieces[c];
        const bool unchanged = pieces_of_old[size_t(from[c])] == 1 && v.triangles.size() == parent.triangles &&
                               v.cap_loops.size() == parent.cap_loops;
        set_target(v, parent, unchanged, now[c], policy, leak);
        if (v.rest_volume > 0.0 && (unchanged || holds_air(v, now[c], b.particles.x))) {
            rebuilt.push_back(uint32_t(out.size()));
            out.push_back(std::move(v));
        }
    }
    b.volumes = std::move(out);
    return result;
}

} // namespace pbdsplat::topology
