#include "topology/cut.h"

#include <algorithm>
#include <cmath>

#include "core/timer.h"
#include "mesh/topology.h"
#include "topology/edit.h"
#include "topology/particle_scratch.h"
#include "topology/volume_policy.h"

namespace pbdsplat::topology {

namespace {

Vec3f crossing_point(const sim::SoftBody& b, uint32_t i, uint32_t j, float u) {
    return sim::xyz(b.particles.x[i]) + u * (sim::xyz(b.particles.x[j]) - sim::xyz(b.particles.x[i]));
}

// Each vertex's signed distance to the cut plane, and its side: -1, +1, or 0 for "on the cut"
// (within its reach, exactly on the plane or snapped there). The triangles the plane crosses
// are found in one lean pass; everything after looks at those only.
// The per-particle arrays come from the thread's scratch (at least the body's size, +1 and 1.0
// where not written: out of reach is the positive side) and go back when the cut ends.
struct Sides {
    std::span<float> distance;
    std::span<int8_t> sign;
    std::vector<uint32_t> looked_at;  // the particles whose entries were written; all when `all`
    bool all = false;
    std::vector<uint32_t> crossed;  // triangles with corners strictly on both sides, ascending
    std::vector<uint32_t> on_cut;   // vertices with sign 0, ascending
};

// Kept by the colour groups through every edit: a sum over the constraints would cost the body.
float mean_rest_length(const sim::SoftBody& b) { return float(b.distance_groups.mean_rest()); }

// The signed distances and the crossed triangles. A cut limited to a list of particles (a
// tear's slit) looks at those, their neighbours and their triangles only; otherwise at all.
void measure_sides(const sim::SoftBody& b, const CutSurface& s, Sides& out) {
    const size_t n = b.particle_count();
    std::span<float> d = out.distance;
    std::span<int8_t> sign = out.sign;
    std::vector<uint32_t>& looked_at = out.looked_at;
    auto measure = [&](uint32_t v) {
        d[v] = s.distance(sim::xyz(b.particles.x[v]));
        sign[v] = d[v] < 0.0f ? int8_t(-1) : int8_t(1);
    };
    auto mixed = [&](const mesh::Triangle& f) {
        const float d0 = d[f[0]], d1 = d[f[1]], d2 = d[f[2]];
        return (d0 < 0.0f || d1 < 0.0f || d2 < 0.0f) && (d0 > 0.0f || d1 > 0.0f || d2 > 0.0f);
    };
    if (s.particles.empty()) {
        // The whole body. A triangle is crossed only where its corners' signs differ (a distance
        // of exactly 0 has sign +1, so the float test decides those few): these two passes are
        // most of a cut's cost on a large body.
        out.all = true;
        for (uint32_t v = 0; v < n; ++v) measure(v);
        for (uint32_t t = 0; t < b.triangles.size(); ++t) {
            const mesh::Triangle& f = b.triangles[t];
            const int8_t s0 = sign[f[0]], s1 = sign[f[1]], s2 = sign[f[2]];
            if ((s0 != s1 || s1 != s2) && mixed(f)) out.crossed.push_back(t);
        }
        return;
    }
    for (uint32_t v : s.particles) {
        looked_at.push_back(v);
        for (const auto& pair : b.rings.ring.of(v)) looked_at.insert(looked_at.end(), pair.begin(), pair.end());
    }
    std::sort(looked_at.begin(), looked_at.end());
    looked_at.erase(std::unique(looked_at.begin(), looked_at.end()), looked_at.end());
    for (uint32_t v : looked_at) measure(v);
    for (uint32_t v : s.particles)
        for (uint32_t t : b.rings.triangles.of(v))
            if (mixed(b.triangles[t])) out.crossed.push_back(t);
    std::sort(out.crossed.begin(), out.crossed.end());
    out.crossed.erase(std::unique(out.crossed.begin(), out.crossed.end()), out.crossed.end());
}

void classify(const sim::SoftBody& b, const CutSurface& s, float snap, float reference, Sides& out) {
    const size_t n = b.particle_count();
    measure_sides(b, s, out);
    const std::span<const float> d = out.distance;
    const std::span<int8_t> sign = out.sign;
    auto each_looked_at = [&](auto&& f) {
        if (out.all)
            for (uint32_t v = 0; v < n; ++v) f(v);
        else
            for (uint32_t v : out.looked_at) f(v);
    };
    bool on_plane = false;
    each_looked_at([&](uint32_t v) { on_plane = on_plane || d[v] == 0.0f; });
    if (on_plane)
        each_looked_at([&](uint32_t v) {
            if (d[v] == 0.0f && s.may_touch(v) && s.reaches(sim::xyz(b.particles.x[v]))) sign[v] = 0;
        });
    // Snap: a crossing near an end moves onto that vertex. Near means within `snap` of the edge,
    // or within `snap` mean edge lengths of rest distance, so repeated cuts through one region
    // cannot make ever smaller triangles. Decided from the unsnapped distances, so the result
    // does not depend on the order edges are visited.
    if (!(reference > 0.0f)) reference = mean_rest_length(b);
    const float reach = snap * reference;
    thread_local ParticleScratch<uint8_t> snaps(0);
    std::vector<uint8_t>& snapped = snaps.take(n);  // a byte per particle: cheaper than a search
    std::vector<uint32_t> on_cut;
    auto snap_to = [&](uint32_t v) {
        if (!snapped[v]) snapped[v] = 1, on_cut.push_back(v);
    };
    for (uint32_t f : out.crossed) {
        const mesh::Triangle& t = b.triangles[f];
        for (int k = 0; k < 3; ++k) {
            const uint32_t i = std::min(t[size_t(k)], t[size_t((k + 1) % 3)]);
            const uint32_t j = std::max(t[size_t(k)], t[size_t((k + 1) % 3)]);
            if (!((d[i] < 0.0f && d[j] > 0.0f) || (d[i] > 0.0f && d[j] < 0.0f))) continue;
            if (!s.may_touch(i) || !s.may_touch(j)) continue;
            const float u = d[i] / (d[i] - d[j]);
            const float rest = (b.rest_positions[j] - b.rest_positions[i]).norm();
            const bool near_i = u < snap || u * rest < reach, near_j = u > 1.0f - snap || (1.0f - u) * rest < reach;
            if (!near_i && !near_j) continue;
            if (s.reaches(crossing_point(b, i, j, u))) snap_to(near_i && (!near_j || u < 0.5f) ? i : j);
        }
    }
    // A crossed triangle's corner piece (the lone vertex and the two crossings) has u_ab * u_ac
    // of its area: where that is a sliver next to the reference triangle, the cut goes through
    // the lone vertex instead. Without this, cuts repeated through one region shrink corners
    // generation after generation (u <= 1 - snap keeps each child above a tenth of its parent,
    // not above any absolute size).
    const float min_corner_area = 0.05f * 0.433f * reference * reference;  // 5 % of an equilateral triangle
    for (uint32_t f : out.crossed) {
        const mesh::Triangle& t = b.triangles[f];
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = t[size_t(k)], p = t[size_t((k + 1) % 3)], q = t[size_t((k + 2) % 3)];
            const bool lone = (d[a] < 0.0f && d[p] > 0.0f && d[q] > 0.0f) || (d[a] > 0.0f && d[p] < 0.0f && d[q] < 0.0f);
            if (!lone || snapped[a] || snapped[p] || snapped[q]) continue;
            if (!s.may_touch(a) || !s.may_touch(p) || !s.may_touch(q)) continue;
            const float u_p = d[a] / (d[a] - d[p]), u_q = d[a] / (d[a] - d[q]);
            const Vec3f& ra = b.rest_positions[a];
            const float area = 0.5f * (b.rest_positions[p] - ra).cross(b.rest_positions[q] - ra).norm();
            if (u_p * u_q * area < min_corner_area && s.reaches(sim::xyz(b.particles.x[a]))) snap_to(a);
        }
    }
    for (uint32_t v : on_cut) sign[v] = 0;
    snaps.give_back(on_cut);
    if (on_plane) {
        on_cut.clear();
        each_looked_at([&](uint32_t v) {
            if (sign[v] == 0) on_cut.push_back(v);
        });
    }
    std::sort(on_cut.begin(), on_cut.end());
    out.on_cut = std::move(on_cut);
}

// The side arrays of this thread, taken for one cut and given back at its end (reset where
// written), whichever way the cut returns.
class SidesLease {
public:
    explicit SidesLease(size_t n) {
        sides.distance = distances().take(n);
        sides.sign = signs().take(n);
    }
    ~SidesLease() {
        if (sides.all) distances().give_back_all(), signs().give_back_all();
        else distances().give_back(sides.looked_at), signs().give_back(sides.looked_at);
    }
    SidesLease(const SidesLease&) = delete;
    SidesLease& operator=(const SidesLease&) = delete;
    Sides sides;

private:
    static ParticleScratch<float>& distances() {
        thread_local ParticleScratch<float> s(1.0f);
        return s;
    }
    static ParticleScratch<int8_t>& signs() {
        thread_local ParticleScratch<int8_t> s(int8_t(1));
        return s;
    }
};

float rest_area(const sim::SoftBody& b, const mesh::Triangle& t) {
    const Vec3f& p = b.rest_positions[t[0]];
    return 0.5f * (b.rest_positions[t[1]] - p).cross(b.rest_positions[t[2]] - p).norm();
}

core::Status validate(const sim::SoftBody& b, const CutSurface& s, const CutOptions& o) {
    if (!(o.snap >= 0.0f && o.snap < 0.5f)) return core::make_error("cut: snap must be in [0, 0.5)");
    if (!(o.reference_edge_length >= 0.0f) || !std::isfinite(o.reference_edge_length))
        return core::make_error("cut: reference_edge_length must be finite and >= 0");
    if (!s.point.allFinite() || !s.normal.allFinite() || std::abs(s.normal.norm() - 1.0f) > 1e-3f)
        return core::make_error("cut: the surface needs a finite point and a unit normal");
    // What the cut reads: every particle, or a listed cut's particles and their neighbours.
    auto broken = [] { return core::make_error("cut: a particle position is not finite; the body is broken"); };
    if (s.particles.empty()) {
        for (const Vec4f& x : b.particles.x)
            if (!x.head<3>().allFinite()) return broken();
        return core::Status::success();
    }
    for (uint32_t v : s.particles) {
        if (v >= b.particle_count()) return core::make_error("cut: the surface lists particle " + std::to_string(v) + " of " +
                                                             std::to_string(b.particle_count()));
        if (!b.particles.x[v].head<3>().allFinite()) return broken();
        for (const auto& pair : b.rings.ring.of(v))
            for (uint32_t w : pair)
                if (!b.particles.x[w].head<3>().allFinite()) return broken();
    }
    return core::Status::success();
}

// Eq. 26: one new particle per crossed edge, shared by both triangles of the edge. Returns the
// triangles crossed (the parents of the re-triangulation).
std::vector<uint32_t> add_crossings(sim::SoftBody& b, const CutSurface& s, const CutOptions& o, const Sides& sides, Edit& e) {
    std::vector<uint32_t> parents;
    for (uint32_t t : sides.crossed) {
        bool crossed = false;
        for (int k = 0; k < 3; ++k) {
            const uint32_t i = std::min(b.triangles[t][size_t(k)], b.triangles[t][size_t((k + 1) % 3)]);
            const uint32_t j = std::max(b.triangles[t][size_t(k)], b.triangles[t][size_t((k + 1) % 3)]);
            if (e.sign[i] * e.sign[j] >= 0) continue;
            if (!s.may_touch(i) || !s.may_touch(j)) continue;
            if (e.point_on(i, j) != UINT32_MAX) {
                crossed = true;
                continue;
            }
            const float di = sides.distance[i], dj = sides.distance[j];
            const float u = std::clamp(di / (di - dj), o.snap, 1.0f - o.snap);
            if (!s.reaches(crossing_point(b, i, j, u))) continue;
            e.add_edge_point(i, j, u);
            crossed = true;
        }
        if (crossed) parents.push_back(t);
    }
    return parents;
}

} // namespace

core::Result<TopologyChange> cut(sim::SoftBody& b, const CutSurface& s, const CutOptions& o) {
    PBDSPLAT_TRY(validate(b, s, o));

    const core::Stopwatch clock;
    core::Stopwatch step;
    const bool grew = sim::reserve_headroom(b);
    Edit e(b);
    e.change.headroom_grown = grew;
    auto lap = [&](const char* name) {
        e.change.phases.push_back({name, step.elapsed_ms()});
        step.restart();
    };
    lap("prepare");
    SidesLease lease(b.particle_count());
    Sides& sides = lease.sides;
    classify(b, s, o.snap, o.reference_edge_length, sides);
    e.sign = sides.sign;
    e.on_cut_vertices = std::move(sides.on_cut);
    lap("classify");

    const std::vector<uint32_t> parents = add_crossings(b, s, o, sides, e);
    lap("crossings");
    e.change.crossed_edges = e.edge_points();
    e.change.crossed_triangles = parents.size();
    if (parents.empty() && e.on_cut_vertices.empty()) {
        e.finish();
        e.change.ms = clock.elapsed_ms();
        return std::move(e.change);
    }
    e.change.components_before = b.pieces;

    // Eq. 27: re-triangulate every crossed triangle around its new particles.
    for (uint32_t t : parents) e.retriangulate(t);
    for (const mesh::TriangleSplit& sp : e.change.splits) {
        const float parent = rest_area(b, e.parent_triangle(sp.parent));
        if (parent > 0.0f) e.change.min_child_area_ratio = std::min(e.change.min_child_area_ratio, rest_area(b, b.triangles[sp.triangle]) / parent);
    }

    lap("retriangulate");
    // Eq. 28: duplicate the vertices on the cut per fan of triangles, then masses, distance
    // constraints and volumes follow the new lists.
    e.split_vertices_along_cut();
    lap("split vertices");
    if (parents.empty() && e.change.duplicated_vertices == 0) {  // touched vertices only, opened nothing
        e.finish();
        e.change.ms = clock.elapsed_ms();
        return std::move(e.change);
    }
    e.update_rings();
    lap("rings");
    e.redistribute_mass();
    lap("mass");
    e.update_distance_constraints();
    lap("distance constraints");
    // Which side of the cut each original particle was on steers the search for the pieces
    // toward the smaller side; only where every particle was classified (not a tear's slit).
    const std::span<const int8_t> side = sides.all ? std::span<const int8_t>(sides.sign).first(e.change.particles_before) : std::span<const int8_t>{};
    const VolumeOutcome volumes = apply_volume_policy(b, o.volume, o.burst_leak, e.local_triangles(), e.change.triangles_before, side);
    b.pieces = volumes.pieces;
    e.change.components_after = b.pieces;
    e.change.loops_fell_back = volumes.loops_fell_back;
    e.change.particles_searched = volumes.particles_searched;
    e.change.searched_whole = volumes.searched_whole;
    e.change.summed_whole = volumes.summed_whole;
    lap("pieces and volumes");
    const core::Stopwatch rebuild;
    sim::rebuild_shape_clusters(b);
    e.change.rebuild_ms = rebuild.elapsed_ms();
    lap("derived solver data");
    e.finish();
    e.change.ms = clock.elapsed_ms();
    return std::move(e.change);
}

} // namespace pbdsplat::topology
