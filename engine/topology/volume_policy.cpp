#include "topology/volume_policy.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/radix_sort.h"
#include "mesh/topology.h"
#include "sim/volume.h"
#include "topology/particle_scratch.h"
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
    v.sealed_below = parent.sealed_below;
    if (unchanged) {
        v.rest_volume = parent.rest_volume;
    } else if (policy == VolumePolicy::rebase) {
        v.rest_volume = now / double(v.pressure);  // the target is the volume it has now
    } else {
        v.rest_volume = parent_now > 0.0 ? parent.rest_volume * now / parent_now : 0.0;
        // Opened: the pressure escapes through the opening, over a few frames.
        if (policy == VolumePolicy::burst && v.opened()) v.leak = std::max(v.leak, leak);
    }
}

// A loop's (or any particle list's) rest-space bounding sphere: centre xyz, radius w.
Vec4f rest_bounds(const sim::SoftBody& b, std::span<const uint32_t> particles) {
    Vec3f lo = b.rest_positions[particles.front()], hi = lo;
    for (uint32_t v : particles) lo = lo.cwiseMin(b.rest_positions[v]), hi = hi.cwiseMax(b.rest_positions[v]);
    const Vec3f c = 0.5f * (lo + hi);
    return {c.x(), c.y(), c.z(), 0.5f * (hi - lo).norm()};
}

bool spheres_meet(const Vec4f& a, const Vec4f& b) {
    const float reach = a.w() + b.w() + 1e-6f;
    return (a.head<3>() - b.head<3>()).squaredNorm() <= reach * reach;
}

void ensure_cap_bounds(const sim::SoftBody& b, sim::VolumeConstraint& c) {
    if (c.cap_bounds.size() == c.cap_loops.size()) return;
    c.cap_bounds.clear();
    for (const auto& loop : c.cap_loops) c.cap_bounds.push_back(rest_bounds(b, loop));
}

void add_loop(const sim::SoftBody& b, Part& part, std::vector<uint32_t>&& loop, const Vec4f& bounds, bool with_caps) {
    if (with_caps) part.caps_six_v += sim::cap_six_volume<float>(loop, b.particles.x);
    part.loops.push_back(std::move(loop));
    part.loop_bounds.push_back(bounds);
}

// The parts of the reached pieces by label, sorted: a handful, where a table over every piece
// would cost a body shredded into thousands of pieces a table that size per cut.
class PartsByLabel {
public:
    struct Entry {
        uint32_t label;
        Part* part;
        sim::VolumeConstraint* rest;  // the constraint the part keeps in place (the first part of a piece)
        bool operator<(const Entry& o) const { return label < o.label; }
    };
    PartsByLabel(std::span<sim::VolumeConstraint* const> parents, std::vector<std::vector<Part>>& parts_of) {
        for (size_t r = 0; r < parts_of.size(); ++r)
            if (parents[r])
                for (Part& part : parts_of[r]) entries_.push_back({part.label, &part, &part == &parts_of[r].front() ? parents[r] : nullptr});
        std::sort(entries_.begin(), entries_.end());
    }
    const Entry* find(uint32_t label) const {
        const auto it = std::lower_bound(entries_.begin(), entries_.end(), Entry{label, nullptr, nullptr});
        return it != entries_.end() && it->label == label ? &*it : nullptr;
    }
    Part* part(uint32_t label) const {
        const Entry* e = find(label);
        return e ? e->part : nullptr;
    }

private:
    std::vector<Entry> entries_;
};

// One parent's loops sorted out: those that stay with the rest are not touched (a loop away from
// the edit and from the parts cut off is settled by its bounds alone, without reading it);
// those the edit reached are listed to be traced again; those on a part cut off move to it.
// `leaving` gets the indices that go, descending. Returns whether the rest's caps follow the
// parent's measure (then they are adjusted here for every loop that leaves).
bool sort_out_loops(const sim::SoftBody& b, std::span<const uint8_t> is_seed, const Vec4f& around, sim::VolumeConstraint& parent,
                    std::vector<Part>& parts, const PartsByLabel& by_label, std::vector<const std::vector<uint32_t>*>& retrace,
                    std::vector<uint32_t>& leaving) {
    ensure_cap_bounds(b, parent);
    Part& rest = parts.front();
    const bool adjusted = !rest.complete && std::isfinite(parent.measured_caps_six_v);
    if (adjusted) rest.caps_six_v = parent.measured_caps_six_v;
    // Bounds of the parts cut off (a pass over their particles, half a body after a cut through
    // the middle): only when there are loops to test against them.
    std::vector<Vec4f> cut_off;
    if (!parent.cap_loops.empty())
        for (size_t k = 1; k < parts.size(); ++k) cut_off.push_back(rest_bounds(b, parts[k].particles));
    for (size_t k = parent.cap_loops.size(); k-- > 0;) {
        const Vec4f& bounds = parent.cap_bounds[k];
        const bool near_edit = spheres_meet(bounds, around);
        const bool near_cut_off = std::any_of(cut_off.begin(), cut_off.end(), [&](const Vec4f& c) { return spheres_meet(c, bounds); });
        if (!near_cut_off && !near_edit) continue;
        std::vector<uint32_t>& loop = parent.cap_loops[k];
        // A loop's bounds are a sphere round all of it: a long loop (a seam round a body cut many
        // times) holds most edits, so its particles are read; a byte per particle makes that a
        // load each (a search of the seeds for each of a 669-particle seam's was 31k of the 222k
        // instructions of a small cut on icosphere:4 after 10,000 others).
        const bool reached = near_edit && std::any_of(loop.begin(), loop.end(), [&](uint32_t v) { return is_seed[v] != 0; });
        Part* to = reached ? nullptr : near_cut_off ? by_label.part(b.piece_of_particle[loop.front()]) : &rest;
        if (to == &rest) continue;
        leaving.push_back(uint32_t(k));
        if (adjusted) rest.caps_six_v -= sim::cap_six_volume<float>(loop, b.particles.x);
        if (reached) retrace.push_back(&loop);
        else if (to) add_loop(b, *to, std::move(loop), bounds, true);
    }
    return adjusted;
}

// The cap loops of the parts of reached pieces that had a volume constraint, and their caps'
// 6V. The first part of a piece (the rest, which keeps its label) keeps its loops where they are,
// in its parent's constraint (sort_out_loops); the reached ones are traced again locally, with
// the boundary edges of the touched triangles, and the new loops appended to their part. A rest
// with a measure takes the measured caps, less the loops it lost and plus those it gained: the
// cost follows the edit (and a bounds test per loop), not the loops' length. Returns false where
// the trace fell back to counting the loops over those parts' triangles.
bool cap_parts(const sim::SoftBody& b, std::span<const uint32_t> seeds, std::span<const uint32_t> touched_triangles,
               std::span<sim::VolumeConstraint* const> parents, std::vector<std::vector<Part>>& parts_of) {
    const Vec4f around = rest_bounds(b, seeds);
    const PartsByLabel by_label(parents, parts_of);
    std::vector<const std::vector<uint32_t>*> retrace;
    std::vector<std::vector<uint32_t>> leaving(parents.size());
    std::vector<uint8_t> adjusted(parents.size(), 0);
    thread_local ParticleScratch<uint8_t> marks(0);
    std::vector<uint8_t>& is_seed = marks.take(b.particle_count());
    for (uint32_t v : seeds) is_seed[v] = 1;
    for (size_t r = 0; r < parents.size(); ++r)
        if (parents[r]) adjusted[r] = sort_out_loops(b, is_seed, around, *parents[r], parts_of[r], by_label, retrace, leaving[r]);
    marks.give_back(seeds);
    std::vector<std::vector<uint32_t>> traced;
    const bool traced_ok = trace_loops(b, touched_triangles, retrace, traced);
    // The loops that left their parent go (swapped with the last: the order of loops is free).
    for (size_t r = 0; r < parents.size(); ++r)
        for (uint32_t k : leaving[r]) {
            sim::VolumeConstraint& c = *parents[r];
            c.cap_loops[k] = std::move(c.cap_loops.back()), c.cap_loops.pop_back();
            c.cap_bounds[k] = c.cap_bounds.back(), c.cap_bounds.pop_back();
        }
    if (!traced_ok) {  // every loop of those parts counted again over their triangles
        traced.clear();
        for (size_t r = 0; r < parents.size(); ++r)
            if (parents[r]) {
                parents[r]->cap_loops.clear(), parents[r]->cap_bounds.clear(), adjusted[r] = 0;
                for (Part& part : parts_of[r]) part.loops.clear(), part.loop_bounds.clear(), part.caps_six_v = 0.0;
            }
        std::vector<mesh::Triangle> triangles;
        for (const mesh::Triangle& t : b.triangles)
            if (by_label.part(b.piece_of_particle[t[0]])) triangles.push_back(t);
        traced = mesh::boundary_loops(triangles, b.particle_count());
    }
    for (auto& loop : traced) {
        const PartsByLabel::Entry* e = by_label.find(b.piece_of_particle[loop[0]]);
        if (!e) continue;
        const Vec4f bounds = rest_bounds(b, loop);
        if (e->rest) {
            e->part->caps_six_v += sim::cap_six_volume<float>(loop, b.particles.x);
            e->rest->cap_loops.push_back(std::move(loop)), e->rest->cap_bounds.push_back(bounds);
        } else {
            add_loop(b, *e->part, std::move(loop), bounds, true);
        }
    }
    for (size_t r = 0; r < parents.size(); ++r)
        if (parents[r] && !adjusted[r]) parts_of[r].front().caps_six_v = sim::caps_six_volume<float>(parents[r]->cap_loops, b.particles.x);
    return traced_ok;
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
// What a parent constraint looked like just before the change, and how to remake it.
struct Remake {
    double caps_before = 0.0;
    size_t loops_before = 0;
    size_t first_new_triangle = 0;
    VolumePolicy policy = VolumePolicy::cap;
    float leak = 0.0f;
};

// The parent constraint becomes its rest's, in place (its untouched loops stay where they are);
// the parts cut off get new constraints in `added`. Returns whether the parent is to go (its
// rest_volume set negative): a piece that holds no air keeps no constraint.
bool remake_constraints(const sim::SoftBody& b, sim::VolumeConstraint& c, std::vector<Part>& parts, const Remake& m,
                        std::vector<sim::VolumeConstraint>& added, size_t& summed_whole) {
    if (!parts.front().complete) sum_rest(b, c, std::span(parts).subspan(1), m.first_new_triangle, parts.front(), summed_whole);
    // The parent's volume just before the change: the edit kept the surface where it was, so its
    // parts' triangles sum to it; its old caps still close it.
    double parent_now = m.caps_before;
    for (const Part& part : parts) parent_now += part.six_v;
    parent_now /= 6.0;
    sim::VolumeConstraint parent;  // the targets' source, without the loops
    parent.rest_volume = c.rest_volume, parent.pressure = c.pressure, parent.compliance = c.compliance, parent.leak = c.leak;
    parent.sealed_below = c.sealed_below;
    const size_t parent_triangles = c.triangle_count;
    bool drop = false;
    for (size_t k = 0; k < parts.size(); ++k) {
        Part& part = parts[k];
        sim::VolumeConstraint fresh;
        sim::VolumeConstraint& v = k == 0 ? c : fresh;
        v.piece = part.label;
        v.triangle_count = part.triangles;
        v.lambda = 0.0;
        if (k > 0) v.cap_loops = std::move(part.loops), v.cap_bounds = std::move(part.loop_bounds);
        const double now = (part.six_v + part.caps_six_v) / 6.0;
        const bool unchanged = parts.size() == 1 && part.triangles == parent_triangles && v.cap_loops.size() == m.loops_before;
        set_target(v, parent, unchanged, now, parent_now, m.policy, m.leak);
        // The unexplored rest of a piece is far larger than what was cut off it: it holds the air
        // it held. Its measures stay usable for a second cut in the same frame.
        const double unmeasured = std::numeric_limits<double>::quiet_NaN();
        v.measured_six_v = part.complete ? unmeasured : part.six_v;
        v.measured_caps_six_v = part.complete ? unmeasured : part.caps_six_v;
        const bool keep = v.rest_volume > 0.0 && (unchanged || !part.complete || holds_air(b, part, now));
        if (k > 0 && keep) added.push_back(std::move(v));
        if (k == 0 && !keep) v.rest_volume = -1.0, drop = true;
    }
    return drop;
}
} // namespace

VolumeOutcome apply_volume_policy(sim::SoftBody& b, VolumePolicy policy, float leak, std::span<const uint32_t> touched_triangles,
                                  size_t first_new_triangle, std::span<const int8_t> side) {
    VolumeOutcome result;
    std::vector<uint32_t> seeds, reached;
    for (uint32_t f : touched_triangles) seeds.insert(seeds.end(), b.triangles[f].begin(), b.triangles[f].end());
    core::radix_sort_unique(seeds);
    for (uint32_t v : seeds) reached.push_back(b.piece_of_particle[v]);
    std::sort(reached.begin(), reached.end());
    reached.erase(std::unique(reached.begin(), reached.end()), reached.end());
    std::vector<sim::VolumeConstraint*> parents(reached.size(), nullptr);
    // The constraints stay in piece order (a piece cut off gets the next label and its constraint
    // goes to the end; topology::check_invariants holds it), so a shredded body's thousands of
    // constraints the edit did not reach are bisected, not read.
    for (size_t r = 0; r < reached.size(); ++r) {
        const auto it = std::lower_bound(b.volumes.begin(), b.volumes.end(), reached[r],
                                         [](const sim::VolumeConstraint& v, uint32_t piece) { return v.piece < piece; });
        if (it != b.volumes.end() && it->piece == reached[r]) parents[r] = &*it;
    }

    // The breadth-first search may look at this many particles before it searches one part at a
    // time: a few rings around the edit, or a sixteenth of the body (a cut through the middle of
    // a large body pays that much before it explores the smaller side).
    const size_t budget = std::max({size_t(2048), 2 * seeds.size(), b.particle_count() / 16});
    std::vector<uint8_t> unmeasured(reached.size(), 0);
    for (size_t r = 0; r < reached.size(); ++r) unmeasured[r] = parents[r] && !std::isfinite(parents[r]->measured_six_v);
    SplitSearch search = split_pieces(b, reached, unmeasured, seeds, budget, side);
    std::vector<std::vector<Part>>& parts_of = search.parts_of;
    result.particles_searched = search.searched;
    result.searched_whole = search.searched_whole;
    result.pieces = b.pieces;
    if (std::none_of(parents.begin(), parents.end(), [](const auto* p) { return p != nullptr; })) return result;
    // The parents' caps just before the change (their old loops still close them), read before
    // the loops move to the parts.
    std::vector<double> caps_before(reached.size(), 0.0);
    std::vector<size_t> loops_before(reached.size(), 0);
    for (size_t r = 0; r < reached.size(); ++r)
        if (const sim::VolumeConstraint* c = parents[r]) {
            caps_before[r] = std::isfinite(c->measured_caps_six_v) ? c->measured_caps_six_v
                                                                   : sim::caps_six_volume<float>(c->cap_loops, b.particles.x);
            loops_before[r] = c->cap_loops.size();
        }
    result.loops_fell_back = !cap_parts(b, seeds, touched_triangles, parents, parts_of);

    std::vector<sim::VolumeConstraint> added;
    bool dropped = false;
    for (size_t r = 0; r < reached.size(); ++r)
        if (parents[r])
            dropped |= remake_constraints(b, *parents[r], parts_of[r], {caps_before[r], loops_before[r], first_new_triangle, policy, leak},
                                          added, result.summed_whole);
    if (dropped) std::erase_if(b.volumes, [](const sim::VolumeConstraint& v) { return v.rest_volume < 0.0; });
    for (sim::VolumeConstraint& v : added) b.volumes.push_back(std::move(v));
    return result;
}

} // namespace pbdsplat::topology
