#include "topology/cut.h"

#include <algorithm>
#include <cmath>
#include <unordered_set>

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

float rest_area(const sim::SoftBody& b, const mesh::Triangle& t) {
    const Vec3f& p = b.rest_positions[t[0]];
    return 0.5f * (b.rest_positions[t[1]] - p).cross(b.rest_positions[t[2]] - p).norm();
}

// Where the cut crosses edge (from, to), as a fraction from `from`, kept `snap` off either end
// (the same fraction eq. 26 places the new particle at).
float crossing_fraction(std::span<const float> d, uint32_t from, uint32_t to, float snap) {
    return std::clamp(d[from] / (d[from] - d[to]), snap, 1.0f - snap);
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

// What the cut will make of the surface, seen before it is made: a node per triangle and side
// (a triangle the cut crosses is split, one node each), joined across an edge where both
// triangles keep part of it on that side. An edge along the cut (both ends on it) joins only
// triangles of one side, as the vertex duplication does. A triangle with corners on both sides
// that the cut does not cross through (where a slit ends) keeps its sides joined.
class SideGraph {
public:
    SideGraph(const sim::SoftBody& b, const CutSurface& s, std::span<const float> d, std::span<const int8_t> sign, float snap)
        : b_(b), s_(s), d_(d), sign_(sign), snap_(snap) {}

    using Node = std::pair<uint32_t, int8_t>;  // triangle, side

    bool has_side(uint32_t t, int8_t s) const {
        for (uint32_t v : b_.triangles[t])
            if (sign_[v] == s) return true;
        return false;
    }

    // The nodes reachable from `start`, in `seen`, stopping once `limit` are found; `cut` false
    // ignores the cut (the surface as it is now). Returns whether the search closed under the limit.
    bool reach(Node start, size_t limit, bool cut, std::vector<Node>& seen) const {
        seen.assign(1, start);
        auto visit = [&](Node n) {
            if (std::ranges::find(seen, n) != seen.end()) return true;
            seen.push_back(n);
            return seen.size() < limit;
        };
        for (size_t i = 0; i < seen.size(); ++i) {
            const auto [t, s] = seen[i];
            if (cut && has_side(t, int8_t(-s)) && !split(t) && !visit({t, int8_t(-s)})) return false;
            const mesh::Triangle& f = b_.triangles[t];
            for (int k = 0; k < 3; ++k) {
                const uint32_t a = f[size_t(k)], c = f[size_t((k + 1) % 3)];
                const bool along = sign_[a] == 0 && sign_[c] == 0;
                if (cut && !along && sign_[a] != s && sign_[c] != s) continue;  // the edge lies across
                for (uint32_t u : b_.rings.triangles.of(a)) {
                    if (u == t || std::ranges::find(b_.triangles[u], c) == b_.triangles[u].end()) continue;
                    if (cut && along && !has_side(u, s)) continue;
                    if (!visit({u, cut ? s : int8_t(1)})) return false;
                }
            }
        }
        return true;
    }

private:
    // Whether the cut crosses every edge of `t` whose ends lie on opposite sides.
    bool split(uint32_t t) const {
        const mesh::Triangle& f = b_.triangles[t];
        for (int k = 0; k < 3; ++k) {
            const uint32_t i = f[size_t(k)], j = f[size_t((k + 1) % 3)];
            if (sign_[i] * sign_[j] >= 0) continue;
            if (!s_.may_touch(i) || !s_.may_touch(j)) return false;
            if (!s_.reaches(crossing_point(b_, i, j, crossing_fraction(d_, i, j, snap_)))) return false;
        }
        return true;
    }

    const sim::SoftBody& b_;
    const CutSurface& s_;
    std::span<const float> d_;
    std::span<const int8_t> sign_;
    float snap_;
};

// Where a cut would close off a fragment: a side of a crossed triangle that reaches fewer than
// `limit` triangles once cut, though it lay in a larger piece before. The nodes met in large
// pieces are remembered, so a large piece is walked once, until the sides move (forget()).
class FragmentSearch {
public:
    FragmentSearch(const SideGraph& graph, uint32_t limit) : graph_(graph), limit_(limit) {}

    // The fragment's (triangle, side) nodes where `start` lies in one, else nullptr.
    const std::vector<SideGraph::Node>* at(SideGraph::Node start) {
        if (large_.contains(key(start))) return nullptr;
        if (!graph_.reach(start, limit_, true, fragment_)) {
            // Everything the search met lies in one piece of at least the limit.
            for (const SideGraph::Node& n : fragment_) large_.insert(key(n));
            return nullptr;
        }
        if (graph_.reach(start, limit_, false, whole_)) return nullptr;  // a small piece before the cut
        return &fragment_;
    }
    void forget() { large_.clear(); }

private:
    static uint64_t key(const SideGraph::Node& n) { return uint64_t(n.first) << 1 | uint64_t(n.second > 0); }
    const SideGraph& graph_;
    uint32_t limit_;
    std::vector<SideGraph::Node> fragment_, whole_;
    std::unordered_set<uint64_t> large_;
};

// Puts a fragment on side `s` over to the other side, so the cut passes it by and it stays on
// what lies beyond: its corners on side `s` change sides, where every corner of side `s` that
// touches them is among them (an edge between a corner that changed and one that did not would be
// crossed with both its ends on one side of the plane). False, and nothing changed, otherwise.
bool join_fragment(const sim::SoftBody& b, std::span<int8_t> sign, const std::vector<SideGraph::Node>& fragment, int8_t s,
                   std::vector<uint32_t>& corners) {
    corners.clear();
    for (const auto& [u, side] : fragment)
        for (uint32_t w : b.triangles[u])
            if (sign[w] == s && std::ranges::find(corners, w) == corners.end()) corners.push_back(w);
    const bool closed = !corners.empty() && std::ranges::all_of(corners, [&](uint32_t w) {
        for (uint32_t u : b.rings.triangles.of(w))
            for (uint32_t x : b.triangles[u])
                if (sign[x] == s && std::ranges::find(corners, x) == corners.end()) return false;
        return true;
    });
    if (closed)
        for (uint32_t w : corners) sign[w] = int8_t(-s);
    return closed;
}

// The smallest child the re-triangulation makes of triangle `t` at these sides, in rest area
// (crossings clamped to [snap, 1 - snap] as add_crossings does); the triangle's own when the
// sides do not cross it.
float smallest_child(const sim::SoftBody& b, const mesh::Triangle& t, std::span<const float> d, std::span<const int8_t> sign, float snap) {
    const float area = rest_area(b, t);
    auto u = [&](uint32_t from, uint32_t to) { return crossing_fraction(d, from, to, snap); };
    for (int k = 0; k < 3; ++k) {
        const uint32_t a = t[size_t(k)], p = t[size_t((k + 1) % 3)], q = t[size_t((k + 2) % 3)];
        if (sign[a] == 0 && sign[p] * sign[q] < 0) {  // through a corner: two children
            const float f = u(p, q);
            return std::min(f, 1.0f - f) * area;
        }
        if (sign[a] != 0 && sign[p] == -sign[a] && sign[q] == -sign[a]) {  // a lone corner: three
            const float fp = u(a, p), fq = u(a, q);
            // The corner, then the quad beyond it split along either diagonal.
            return std::min({fp * fq, 1.0f - fp, fp * (1.0f - fq), 1.0f - fq, fq * (1.0f - fp)}) * area;
        }
    }
    return area;
}

// A snap can close off a few triangles: an ear at an opening whose two inner corners both snap
// onto the cut leaves as a piece of one triangle, since the cut then runs along its inner edge.
// Such a fragment is a fleck no user drew: its snapped corners go back to their sides (the cut
// crosses the edges beside them instead), unless that would make a child below `min_child`
// (the snaps exist to keep cuts repeated through one region from whittling triangles down).
// A piece that was small before the cut is left to pass_small_pieces.
void keep_fragments(const sim::SoftBody& b, const CutSurface& cut, std::span<const float> d, std::span<int8_t> sign,
                    std::span<const uint8_t> snapped, const std::vector<uint32_t>& on_cut, uint32_t min_fragment, float snap,
                    float min_child) {
    const SideGraph graph(b, cut, d, sign, snap);
    FragmentSearch search(graph, min_fragment);
    std::vector<uint32_t> corners;
    auto unsnap = [&] {
        for (uint32_t w : corners) sign[w] = d[w] < 0.0f ? int8_t(-1) : int8_t(1);
        for (uint32_t w : corners)
            for (uint32_t t : b.rings.triangles.of(w))
                if (smallest_child(b, b.triangles[t], d, sign, snap) < min_child) {
                    for (uint32_t x : corners) sign[x] = 0;
                    return false;
                }
        return true;
    };
    for (int round = 0; round < 4; ++round) {
        bool changed = false;
        for (uint32_t v : on_cut) {
            if (!snapped[v] || sign[v] != 0) continue;
            for (uint32_t t : b.rings.triangles.of(v)) {
                // A snap closes a fragment off along an edge of the cut: seeded there only.
                const mesh::Triangle& f = b.triangles[t];
                if ((sign[f[0]] == 0) + (sign[f[1]] == 0) + (sign[f[2]] == 0) != 2) continue;
                for (int8_t s : {int8_t(-1), int8_t(1)}) {
                    if (sign[v] != 0 || !graph.has_side(t, s)) continue;
                    const std::vector<SideGraph::Node>* fragment = search.at({t, s});
                    if (!fragment) continue;
                    corners.clear();
                    for (const auto& [u, side] : *fragment)
                        for (uint32_t w : b.triangles[u])
                            if (snapped[w] && sign[w] == 0 && std::ranges::find(corners, w) == corners.end()) corners.push_back(w);
                    // Where unsnapping would make a sliver, the fragment goes over to the other
                    // side whole instead (a teapot cut by 40 planes kept 6 such flecks, the
                    // smallest of one triangle).
                    changed = unsnap() || join_fragment(b, sign, *fragment, s, corners) || changed;
                }
            }
        }
        if (!changed) break;
        search.forget();  // the sides moved
    }
}

// A cut can close off a few triangles where nothing snapped: a stroke across the rim of a
// model's small part (a monkey's eye decimated to a few dozen triangles) parts a cap of three
// from it, which flies off as a speck. Such a cap changes sides instead (join_fragment), so the
// cut passes it by and it stays on the part.
void join_crossed_fragments(const sim::SoftBody& b, const CutSurface& cut, std::span<const float> d, std::span<int8_t> sign,
                            const std::vector<uint32_t>& crossed, uint32_t min_fragment, float snap) {
    const SideGraph graph(b, cut, d, sign, snap);
    FragmentSearch search(graph, min_fragment);
    std::vector<uint32_t> corners;
    for (uint32_t t : crossed)
        for (int8_t s : {int8_t(-1), int8_t(1)}) {
            if (!graph.has_side(t, s) || !graph.has_side(t, int8_t(-s))) continue;
            const std::vector<SideGraph::Node>* fragment = search.at({t, s});
            if (fragment) join_fragment(b, sign, *fragment, s, corners);
        }
}

// A fleck (a piece of fewer than `min_fragment` triangles: one an earlier cut could not help
// leaving) is passed by, every corner of it put on the side most of it lies on: parted, it only
// makes smaller flecks (a teapot cut by 40 planes ended with pieces of one triangle among its 122).
void pass_small_pieces(const sim::SoftBody& b, std::span<const float> d, std::span<int8_t> sign, const std::vector<uint32_t>& crossed,
                       std::span<const uint32_t> on_cut, uint32_t min_fragment) {
    const size_t most = min_fragment;
    std::vector<uint32_t> seeds = crossed, piece_triangles, seen_pieces;
    for (uint32_t v : on_cut)
        for (uint32_t t : b.rings.triangles.of(v)) seeds.push_back(t);
    for (uint32_t seed : seeds) {
        const uint32_t piece = b.piece_of_particle[b.triangles[seed][0]];
        if (std::ranges::find(seen_pieces, piece) != seen_pieces.end()) continue;
        seen_pieces.push_back(piece);
        // Its triangles, flooded through shared corners until there are too many to matter.
        piece_triangles.assign(1, seed);
        for (size_t k = 0; k < piece_triangles.size() && piece_triangles.size() < most; ++k)
            for (uint32_t v : b.triangles[piece_triangles[k]])
                for (uint32_t t : b.rings.triangles.of(v))
                    if (std::ranges::find(piece_triangles, t) == piece_triangles.end()) piece_triangles.push_back(t);
        if (piece_triangles.size() >= most) continue;
        double side = 0.0;
        for (uint32_t t : piece_triangles)
            for (uint32_t v : b.triangles[t]) side += double(d[v]);
        for (uint32_t t : piece_triangles)
            for (uint32_t v : b.triangles[t]) sign[v] = side < 0.0 ? int8_t(-1) : int8_t(1);
    }
}

// The vertices a cut moves onto itself: a byte per particle, and the list of those set.
struct Snaps {
    std::vector<uint8_t>& flag;
    std::vector<uint32_t> on_cut;
    void add(uint32_t v) {
        if (!flag[v]) flag[v] = 1, on_cut.push_back(v);
    }
};

// A corner piece below this share of an equilateral triangle of the reference edge is a sliver.
constexpr float k_min_corner_share = 0.05f;
constexpr float k_equilateral_area = 0.433f;  // sqrt(3) / 4, of a unit edge
// Undoing a snap to keep a fragment whole may make children down to this share of the corner
// bound (0.5 % of the equilateral triangle): at 2.5 % bunny_cut's ear stayed a fleck, at 0.25 %
// cuts repeated through one region whittled triangles to 1.2e-4 of the mean area (2.4e-4 without).
constexpr float k_fragment_child_share = 0.1f;

// Snap: a crossing near an end moves onto that vertex. Near means within `snap` of the edge, or
// within `reach` of rest distance (snap mean edge lengths), so repeated cuts through one region
// cannot make ever smaller triangles. Decided from the unsnapped distances, so the result does
// not depend on the order edges are visited.
void snap_near_crossings(const sim::SoftBody& b, const CutSurface& s, std::span<const float> d, float snap, float reach,
                         const std::vector<uint32_t>& crossed, Snaps& out) {
    for (uint32_t f : crossed) {
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
            if (s.reaches(crossing_point(b, i, j, u))) out.add(near_i && (!near_j || u < 0.5f) ? i : j);
        }
    }
}

// A crossed triangle's corner piece (the lone vertex and the two crossings) has u_ab * u_ac of
// its area: where that is below `min_corner_area`, the cut goes through the lone vertex instead.
// Without this, cuts repeated through one region shrink corners generation after generation
// (u <= 1 - snap keeps each child above a tenth of its parent, not above any absolute size).
void snap_sliver_corners(const sim::SoftBody& b, const CutSurface& s, std::span<const float> d, float min_corner_area,
                         const std::vector<uint32_t>& crossed, Snaps& out) {
    for (uint32_t f : crossed) {
        const mesh::Triangle& t = b.triangles[f];
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = t[size_t(k)], p = t[size_t((k + 1) % 3)], q = t[size_t((k + 2) % 3)];
            const bool lone = (d[a] < 0.0f && d[p] > 0.0f && d[q] > 0.0f) || (d[a] > 0.0f && d[p] < 0.0f && d[q] < 0.0f);
            if (!lone || out.flag[a] || out.flag[p] || out.flag[q]) continue;
            if (!s.may_touch(a) || !s.may_touch(p) || !s.may_touch(q)) continue;
            const float u_p = d[a] / (d[a] - d[p]), u_q = d[a] / (d[a] - d[q]);
            const Vec3f& ra = b.rest_positions[a];
            const float area = 0.5f * (b.rest_positions[p] - ra).cross(b.rest_positions[q] - ra).norm();
            if (u_p * u_q * area < min_corner_area && s.reaches(sim::xyz(b.particles.x[a]))) out.add(a);
        }
    }
}

void classify(const sim::SoftBody& b, const CutSurface& s, float snap, float reference, uint32_t min_fragment, Sides& out) {
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
    if (!(reference > 0.0f)) reference = mean_rest_length(b);
    thread_local ParticleScratch<uint8_t> snaps(0);
    Snaps snapped{snaps.take(n), {}};  // a byte per particle: cheaper than a search
    snap_near_crossings(b, s, d, snap, snap * reference, out.crossed, snapped);
    const float min_corner_area = k_min_corner_share * k_equilateral_area * reference * reference;
    snap_sliver_corners(b, s, d, min_corner_area, out.crossed, snapped);
    std::vector<uint32_t>& on_cut = snapped.on_cut;
    for (uint32_t v : on_cut) sign[v] = 0;
    // A tear's slit (a listed cut) has its own rule: tear_once takes back a slit that leaves a
    // small piece and tries the next edge.
    if (min_fragment > 0 && out.all) {
        keep_fragments(b, s, d, sign, snapped.flag, on_cut, min_fragment, snap, k_fragment_child_share * min_corner_area);
        join_crossed_fragments(b, s, d, sign, out.crossed, min_fragment, snap);
        pass_small_pieces(b, d, sign, out.crossed, on_cut, min_fragment);
    }
    snaps.give_back(on_cut);
    std::erase_if(on_cut, [&](uint32_t v) { return sign[v] != 0; });
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
            const float u = crossing_fraction(sides.distance, i, j, o.snap);
            if (!s.reaches(crossing_point(b, i, j, u))) continue;
            e.add_edge_point(i, j, u);
            crossed = true;
        }
        if (crossed) parents.push_back(t);
    }
    return parents;
}

// Eq. 27: re-triangulate every crossed triangle around its new particles.
void retriangulate(const sim::SoftBody& b, Edit& e, std::span<const uint32_t> parents) {
    for (uint32_t t : parents) e.retriangulate(t);
    for (const mesh::TriangleSplit& sp : e.change.splits) {
        const float parent = rest_area(b, e.parent_triangle(sp.parent));
        if (parent > 0.0f) e.change.min_child_area_ratio = std::min(e.change.min_child_area_ratio, rest_area(b, b.triangles[sp.triangle]) / parent);
    }
}

// After the vertices are split: rings, masses and distance constraints follow the new lists,
// then the pieces and their volumes. `lap(name)` times each phase.
template <class Lap>
void follow_split(sim::SoftBody& b, Edit& e, const CutOptions& o, const Sides& sides, Lap& lap) {
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
}

// A weld the cut passes between (its two particles on either side, where the cut reaches) is
// cut with it: a teapot cut in two is two objects, not one held across the cut by its lid's
// welds. A tear's slit (a listed cut) leaves them: it runs through the skin beside a weld.
void sever_crossed_welds(sim::SoftBody& b, const CutSurface& s) {
    if (!s.particles.empty()) return;
    std::erase_if(b.welds, [&](const sim::DistanceConstraint& w) {
        if (!w.alive()) return false;
        const Vec3f xi = sim::xyz(b.particles.x[w.i]), xj = sim::xyz(b.particles.x[w.j]);
        const float di = s.distance(xi), dj = s.distance(xj);
        if (!((di < 0.0f && dj > 0.0f) || (di > 0.0f && dj < 0.0f))) return false;
        return s.reaches(xi + (xj - xi) * (di / (di - dj)));
    });
}

} // namespace

core::Result<TopologyChange> cut(sim::SoftBody& b, const CutSurface& s, const CutOptions& o) {
    PBDSPLAT_TRY(validate(b, s, o));
    // The copies a cut makes take their source's mass: a sleeping piece's is held (sim/sleep.h).
    sim::wake_all(b);

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
    classify(b, s, o.snap, o.reference_edge_length, o.min_fragment_triangles, sides);
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

    retriangulate(b, e, parents);

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
    follow_split(b, e, o, sides, lap);
    sever_crossed_welds(b, s);
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
