#include "topology/volume_policy.h"

#include <algorithm>
#include <cmath>

#include "mesh/topology.h"
#include "sim/volume.h"
#include "topology/piece_split.h"

namespace pbdsplat::topology {

namespace {
// A part too thin or too small to hold air: a flake torn off a shell, a sliver of a few
// triangles. Its capped volume is nearly zero against its area, so a volume constraint on it
// has a tiny gradient and a projection step of C / |grad|^2 that flings its particles away: it
// gets none and moves as cloth. A sphere scores V / A^1.5 = 0.094, a shallow dome of height
// 0.05 r about 0.014. The bound on the area settles most parts without a square root each.
bool holds_air(const sim::SoftBody& b, const Part& part, double volume) {
    if (part.triangles < 12) return false;
    if (std::abs(volume) >= 0.01 * std::pow(part.area_bound, 1.5)) return true;
    const double area = part_area(b, part);
    return area > 0.0 && std::abs(volume) / std::pow(area, 1.5) >= 0.01;
}

// Edge (a, b) of triangle t is on the boundary when no other triangle has both ends.
bool on_boundary(const sim::SoftBody& body, uint32_t t, uint32_t a, uint32_t b) {
    return sim::edge_on_boundary(body.rings, body.triangles, t, a, b);
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
// A part's target volume by the policy, from its parent's (`parent_now`: the parent's volume
// just before the change).
void set_target(sim::VolumeConstraint& v, const sim::VolumeConstraint& parent, bool unchanged, double now, double parent_now,
                VolumePolicy policy, float leak) {
    v.pressure = parent.pressure;
    v.compliance = parent.compliance;
    v.leak = parent.leak;
    if (unchanged) {
        v.rest_volume = parent.rest_volume;
    } else if (policy == VolumePolicy::rebase) {
        v.rest_volume = now / double(v.pressure);  // the target is the volume it has now
    } else {
        v.rest_volume = parent_now > 0.0 ? parent.rest_volume * now / parent_now : 0.0;
        // Opened: the pressure escapes through the opening, over a few frames.
        if (policy == VolumePolicy::burst && !v.cap_loops.empty()) v.leak = std::max(v.leak, leak);
    }
}

// The cap loops of the parts of reached pieces that had a volume constraint: the parent's
// loops that kept clear of the edit stay as they were, the rest are traced locally. Returns
// false where the trace fell back to counting the loops over those parts' triangles.
bool cap_parts(const sim::SoftBody& b, std::span<const uint32_t> seeds, std::span<const uint32_t> touched_triangles,
               std::span<const sim::VolumeConstraint* const> parents, std::vector<std::vector<Part>>& parts_of) {
    std::vector<std::vector<uint32_t>> loops;
    std::vector<const std::vector<uint32_t>*> retrace;
    for (const sim::VolumeConstraint* parent : parents) {
        if (!parent) continue;
        for (const std::vector<uint32_t>& loop : parent->cap_loops) {
            const bool reached = std::any_of(loop.begin(), loop.end(), [&](uint32_t v) { return std::binary_search(seeds.begin(), seeds.end(), v); });
            if (reached) retrace.push_back(&loop);
            else loops.push_back(loop);
        }
    }
    std::vector<Part*> part_of_label(b.pieces, nullptr);
    for (size_t r = 0; r < parts_of.size(); ++r)
        if (parents[r])
            for (Part& part : parts_of[r]) part_of_label[part.label] = &part;
    const bool traced = trace_loops(b, touched_triangles, retrace, loops);
    if (!traced) {
        std::vector<mesh::Triangle> triangles;
        for (const mesh::Triangle& t : b.triangles)
            if (part_of_label[b.piece_of_particle[t[0]]]) triangles.push_back(t);
        loops = mesh::boundary_loops(triangles, b.particle_count());
    }
    for (auto& loop : loops)
        if (Part* part = part_of_label[b.piece_of_particle[loop[0]]]) part->loops.push_back(std::move(loop));
    return traced;
}

// The rest of a piece that the local search left unexplored: its triangle count from the
// parent's, what the edit appended to it and what was cut off; its triangles' 6V from the
// solver's last measure of the parent less what was cut off (the edit keeps the surface where
// it was), or summed over the body's triangles where there is no measure (counted).
void sum_rest(const sim::SoftBody& b, const sim::VolumeConstraint& parent, std::span<const Part> cut_off, size_t first_new_triangle,
              Part& rest, size_t& summed_whole) {
    // Appended triangles of the old piece: now labelled with the rest's label or a cut-off part's.
    auto of_old_piece = [&](uint32_t label) {
        return label == rest.label || std::any_of(cut_off.begin(), cut_off.end(), [&](const Part& p) { return p.label == label; });
    };
    rest.triangles = parent.triangle_count;
    for (size_t t = first_new_triangle; t < b.triangles.size(); ++t) rest.triangles += of_old_piece(b.piece_of_particle[b.triangles[t][0]]);
    double cut_six_v = 0.0;
    for (const Part& part : cut_off) rest.triangles -= part.triangles, cut_six_v += part.six_v;
    if (std::isfinite(parent.measured_six_v)) {
        rest.six_v = parent.measured_six_v - cut_six_v;
    } else {
        rest.six_v = sim::triangles_six_volume<float>(b.triangles, b.piece_of_particle, rest.label, b.particles.x);
        ++summed_whole;
    }
}
} // namespace

VolumeOutcome apply_volume_policy(sim::SoftBody& b, VolumePolicy policy, float leak, std::span<const uint32_t> touched_triangles,
                                  size_t first_new_triangle) {
    VolumeOutcome result;
    std::vector<uint32_t> seeds, reached;
    for (uint32_t f : touched_triangles) seeds.insert(seeds.end(), b.triangles[f].begin(), b.triangles[f].end());
    std::sort(seeds.begin(), seeds.end());
    seeds.erase(std::unique(seeds.begin(), seeds.end()), seeds.end());
    for (uint32_t v : seeds) reached.push_back(b.piece_of_particle[v]);
    std::sort(reached.begin(), reached.end());
    reached.erase(std::unique(reached.begin(), reached.end()), reached.end());
    std::vector<const sim::VolumeConstraint*> parents(reached.size(), nullptr);
    for (const sim::VolumeConstraint& v : b.volumes)
        if (auto it = std::lower_bound(reached.begin(), reached.end(), v.piece); it != reached.end() && *it == v.piece)
            parents[size_t(it - reached.begin())] = &v;

    // The local search may look at this many particles before it searches the pieces whole: a
    // few rings around the edit, or a sixteenth of the body (a cut through the middle of a large
    // body pays that much extra before the whole search).
    const size_t budget = std::max({size_t(2048), 2 * seeds.size(), b.particle_count() / 16});
    SplitSearch search = split_pieces(b, reached, seeds, budget);
    std::vector<std::vector<Part>>& parts_of = search.parts_of;
    result.particles_searched = search.searched;
    result.searched_whole = search.searched_whole;
    result.pieces = b.pieces;
    if (std::none_of(parents.begin(), parents.end(), [](const auto* p) { return p != nullptr; })) return result;
    result.loops_fell_back = !cap_parts(b, seeds, touched_triangles, parents, parts_of);

    std::vector<sim::VolumeConstraint> out;
    for (sim::VolumeConstraint& c : b.volumes) {
        const auto it = std::lower_bound(reached.begin(), reached.end(), c.piece);
        if (it == reached.end() || *it != c.piece) {  // a piece the change did not reach keeps its constraint as it was
            out.push_back(std::move(c));
            continue;
        }
        std::vector<Part>& parts = parts_of[size_t(it - reached.begin())];
        if (!parts.front().complete) sum_rest(b, c, std::span(parts).subspan(1), first_new_triangle, parts.front(), result.summed_whole);
        // The parent's volume just before the change: the edit kept the surface where it was,
        // so its parts' triangles sum to it; its old caps still close it.
        double parent_now = sim::caps_six_volume<float>(c.cap_loops, b.particles.x);
        for (const Part& part : parts) parent_now += part.six_v;
        parent_now /= 6.0;
        for (Part& part : parts) {
            sim::VolumeConstraint v;
            v.piece = part.label;
            v.triangle_count = part.triangles;
            v.cap_loops = std::move(part.loops);
            const double now = (part.six_v + sim::caps_six_volume<float>(v.cap_loops, b.particles.x)) / 6.0;
            const bool unchanged = parts.size() == 1 && part.triangles == c.triangle_count && v.cap_loops.size() == c.cap_loops.size();
            set_target(v, c, unchanged, now, parent_now, policy, leak);
            // The unexplored rest of a piece is far larger than what was cut off it: it holds
            // the air it held. Its measure stays usable for a second cut in the same frame.
            if (!part.complete) v.measured_six_v = part.six_v;
            if (v.rest_volume > 0.0 && (unchanged || !part.complete || holds_air(b, part, now))) out.push_back(std::move(v));
        }
    }
    b.volumes = std::move(out);
    return result;
}

} // namespace pbdsplat::topology
