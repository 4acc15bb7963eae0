#include "topology/tear.h"

#include <algorithm>
#include <cmath>

#include "topology/cut_surface.h"

namespace pbdsplat::topology {

core::Status validate(const TearOptions& o) {
    if (!(o.threshold > 1.0f) || !std::isfinite(o.threshold))
        return core::make_error("tear threshold must be a stretch ratio above 1 (got " + std::to_string(o.threshold) + ")");
    if (o.max_per_frame == 0) return core::make_error("tear: max_per_frame must be at least 1");
    if (!(o.reach >= 0.5f) || !std::isfinite(o.reach)) return core::make_error("tear: reach must be at least 0.5 edge lengths");
    if (o.tip_threshold != 0.0f && !(o.tip_threshold > 1.0f && o.tip_threshold <= o.threshold))
        return core::make_error("tear: tip_threshold must be a stretch ratio above 1 and at most the threshold (got " + std::to_string(o.tip_threshold) + ")");
    if (!(o.gauge >= 0.0f) || !std::isfinite(o.gauge)) return core::make_error("tear: gauge must be a length >= 0");
    if (o.min_fragment_triangles > 1000000) return core::make_error("tear: min_fragment_triangles must be at most 1,000,000");
    return core::Status::success();
}

namespace {
// Stretch ratios: the same arithmetic wherever an edge is measured, so that the frame's set and
// a fresh scan agree to the bit. Most edges are far from tearing; a squared test with a margin
// (0.1 % of the stretch past 1, far above float rounding) passes them over without the square
// root and the division, and decides nothing the exact test below would not.
struct RatioTest {
    RatioTest(float at, float front_at, const CrackFront* on_front, float gauge_length)
        : threshold(at), front_threshold(on_front ? front_at : at), front(on_front), gauge(gauge_length),
          margin(0.999f * (std::min(at, front_threshold) - 1.0f)) {}
    // The edge when past its threshold (the front's where an end is on it), else excess 0. The
    // ratio is 1 plus the lengthening over the longer of the rest length and the gauge.
    StrainedEdge operator()(const sim::SoftBody& b, const sim::DistanceConstraint& c) const {
        StrainedEdge e{c.i, c.j, 0.0f, 0.0f};
        if (!(c.rest > 0.0f)) return e;
        const Vec3f d = (b.particles.x[c.i] - b.particles.x[c.j]).head<3>();
        const float over = std::max(c.rest, gauge);
        const float least = c.rest + margin * over;
        if (d.squaredNorm() < least * least) return e;
        e.ratio = 1.0f + (d.norm() - c.rest) / over;
        const float at = front && (front->on(c.i) || front->on(c.j)) ? front_threshold : threshold;
        if (e.ratio > at) e.excess = e.ratio / at;
        return e;
    }
    float threshold, front_threshold;
    const CrackFront* front;
    float gauge, margin;
};

bool more_strained(const StrainedEdge& x, const StrainedEdge& y) {
    if (x.excess != y.excess) return x.excess > y.excess;
    if (x.ratio != y.ratio) return x.ratio > y.ratio;
    return x.i != y.i ? x.i < y.i : x.j < y.j;
}

// Whether any of `particles` lies on an open edge (a neighbour it shares only one triangle with).
// A slit can cut a piece off only by reaching an opening (or by closing a loop of its own, which
// one short slit does not): away from openings a tear needs no copy of the body to go back to.
bool touches_opening(const sim::SoftBody& b, std::span<const uint32_t> particles) {
    std::vector<uint32_t> seen;
    for (uint32_t v : particles) {
        seen.clear();
        for (const auto& pair : b.rings.ring.of(v)) seen.insert(seen.end(), pair.begin(), pair.end());
        std::sort(seen.begin(), seen.end());
        for (size_t k = 0; k < seen.size();) {
            size_t run = 1;
            while (k + run < seen.size() && seen[k + run] == seen[k]) ++run;
            if (run == 1) return true;
            k += run;
        }
    }
    return false;
}
std::vector<StrainedEdge> strained(const sim::SoftBody& b, const RatioTest& test, size_t limit) {
    std::vector<StrainedEdge> out;
    for (const sim::DistanceConstraint& c : b.distance)
        if (const StrainedEdge e = test(b, c); e.excess > 0.0f) out.push_back(e);
    const size_t n = std::min(out.size(), limit);
    std::partial_sort(out.begin(), out.begin() + ptrdiff_t(n), out.end(), more_strained);
    out.resize(n);
    return out;
}
} // namespace

std::vector<StrainedEdge> strained_edges(const sim::SoftBody& b, float threshold, size_t limit, float gauge) {
    return strained(b, RatioTest(threshold, threshold, nullptr, gauge), limit);
}

float tear_gauge(const sim::SoftBody& b) { return float(b.distance_groups.mean_rest()); }

std::vector<uint32_t> CrackFront::grow(const sim::SoftBody& b, const TopologyChange& change) {
    if (flags_.size() < change.particles_after) flags_.resize(change.particles_after, 0);
    std::fill(flags_.begin() + ptrdiff_t(change.particles_before), flags_.begin() + ptrdiff_t(change.particles_after), uint8_t(1));
    std::vector<uint32_t> joined;
    for (uint32_t t : change.touched_triangles)
        for (uint32_t v : b.triangles[t])
            if (!flags_[v] && touches_opening(b, std::span(&v, 1))) flags_[v] = 1, joined.push_back(v);
    return joined;
}

StrainedSet::StrainedSet(const sim::SoftBody& b, float threshold, float gauge)
    : threshold_(threshold), front_threshold_(threshold), gauge_(gauge) {
    edges_ = strained_edges(b, threshold, SIZE_MAX, gauge);
}

StrainedSet::StrainedSet(const sim::SoftBody& b, float threshold, float front_threshold, CrackFront& front, float gauge)
    : threshold_(threshold), front_threshold_(front_threshold), gauge_(gauge), front_(&front) {
    edges_ = strained(b, RatioTest(threshold_, front_threshold_, front_, gauge_), SIZE_MAX);
}

void StrainedSet::sort() { std::sort(edges_.begin(), edges_.end(), more_strained); }

void StrainedSet::update(const sim::SoftBody& b, const TopologyChange& change) {
    if (!change.changed()) return;
    const std::vector<uint32_t> joined = front_ ? front_->grow(b, change) : std::vector<uint32_t>{};
    const RatioTest test(threshold_, front_threshold_, front_, gauge_);
    const sim::DistanceGroups& groups = b.distance_groups;
    // An edge stays while a live constraint joins its ends with the same rest length (its ratio
    // then is what it was: neither end moved).
    std::erase_if(edges_, [&](const StrainedEdge& e) {
        if (e.i >= b.particle_count()) return true;
        for (uint32_t slot : groups.of_particle.of(e.i)) {
            const sim::DistanceConstraint& c = b.distance[slot];
            if (c.alive() && ((c.i == e.i && c.j == e.j) || (c.i == e.j && c.j == e.i))) return test(b, c).excess != e.excess;
        }
        return true;
    });
    // The constraints the change added: each has a new particle at one end.
    const uint32_t first_new = uint32_t(change.particles_before);
    for (uint32_t v = first_new; v < change.particles_after; ++v)
        for (uint32_t slot : groups.of_particle.of(v)) {
            const sim::DistanceConstraint& c = b.distance[slot];
            const uint32_t other = c.i == v ? c.j : c.i;
            if (!c.alive() || (other >= first_new && other < v)) continue;  // an edge between two new particles: once
            if (const StrainedEdge s = test(b, c); s.excess > 0.0f) edges_.push_back(s);
        }
    // The old particles that joined the front: their edges pass at its threshold now (those with a
    // new particle at the other end were added above).
    for (uint32_t v : joined)
        for (uint32_t slot : groups.of_particle.of(v)) {
            const sim::DistanceConstraint& c = b.distance[slot];
            if (c.alive() && (c.i == v ? c.j : c.i) < first_new)
                if (const StrainedEdge s = test(b, c); s.excess > 0.0f) edges_.push_back(s);
        }
    sort();
    // An edge between two that joined, or one whose excess the front left as it was, came twice.
    edges_.erase(std::unique(edges_.begin(), edges_.end(), [](const StrainedEdge& x, const StrainedEdge& y) { return x.i == y.i && x.j == y.j; }),
                 edges_.end());
}

namespace {
// Whether a plane through v with this normal has v's ring on both sides, so that cutting there
// splits v's fan in two; and how far the ring reaches.
bool splits_ring(const sim::SoftBody& b, uint32_t v, const Vec3f& normal, float& radius) {
    if (b.particles.w[v] == 0.0f) return false;  // a pinned particle holds; tear at the other end
    const Vec3f xv = sim::xyz(b.particles.x[v]);
    bool pos = false, neg = false;
    radius = 0.0f;
    for (const auto& r : b.rings.ring.of(v))
        for (uint32_t w : r) {
            const Vec3f xw = sim::xyz(b.particles.x[w]);
            const float d = normal.dot(xw - xv), len = (xw - xv).norm();
            pos = pos || d > 0.25f * len;
            neg = neg || d < -0.25f * len;
            radius = std::max(radius, len);
        }
    return pos && neg;
}
// The particles within `rings` triangle rings of v, ascending.
std::vector<uint32_t> neighbourhood(const sim::SoftBody& b, uint32_t v, int rings) {
    std::vector<uint32_t> in{v}, front{v}, next;
    for (int r = 0; r < rings; ++r) {
        next.clear();
        for (uint32_t u : front)
            for (const auto& pair : b.rings.ring.of(u)) next.insert(next.end(), pair.begin(), pair.end());
        std::sort(next.begin(), next.end());
        next.erase(std::unique(next.begin(), next.end()), next.end());
        std::erase_if(next, [&](uint32_t w) { return std::binary_search(in.begin(), in.end(), w); });
        in.insert(in.end(), next.begin(), next.end());
        std::sort(in.begin(), in.end());
        front.swap(next);
    }
    return in;
}

// Pieces with fewer than `below` triangles.
size_t small_pieces(const sim::SoftBody& b, uint32_t below) {
    if (below == 0) return 0;
    const std::vector<size_t> count = sim::piece_triangle_counts(b.triangles, b.piece_of_particle, b.pieces);
    return size_t(std::count_if(count.begin(), count.end(), [&](size_t c) { return c < below; }));
}
constexpr int k_refusals_per_call = 2;

} // namespace

core::Result<std::optional<TopologyChange>> tear_once(sim::SoftBody& b, const TearOptions& tear, const CutOptions& cut_options,
                                                      StrainedSet& strained) {
    PBDSPLAT_TRY(validate(tear));
    const size_t small_before = small_pieces(b, tear.min_fragment_triangles);
    int refusals = 0;
    // The most strained edges first; the first that can open does. A copy: a refused tear puts
    // the frame's set back.
    const std::span<const StrainedEdge> top = strained.most_strained(16);
    const std::vector<StrainedEdge> candidates(top.begin(), top.end());
    // A held particle never splits: what is strained enough to tear must be free first.
    if (!candidates.empty()) sim::wake_all(b);
    for (const StrainedEdge& e : candidates) {
        const Vec3f xi = sim::xyz(b.particles.x[e.i]), xj = sim::xyz(b.particles.x[e.j]);
        const Vec3f along = (xj - xi).normalized();
        // Split an end vertex across the edge: the plane through it, normal to the edge. Its fan
        // parts into the side that keeps the edge and the side that pulled it long.
        for (uint32_t v : {e.i, e.j}) {
            float radius = 0.0f;
            if (!splits_ring(b, v, along, radius)) continue;
            CutSurface slit = local_cut(sim::xyz(b.particles.x[v]), along, std::max(tear.reach * (xj - xi).norm(), 1.01f * radius));
            slit.particles = neighbourhood(b, v, 2);
            // Whether the slit cuts off a fleck shows only once it is cut: the body as it was is
            // kept to go back to. The slit crosses the triangles of its particles, whose corners
            // reach a ring further: an opening there can close a piece off too (teapot_balloon's
            // pull cut off 6 triangles so).
            std::optional<sim::SoftBody> before;
            if (tear.min_fragment_triangles > 0 && touches_opening(b, neighbourhood(b, v, 3))) before.emplace(b);
            auto change = cut(b, slit, cut_options);
            if (!change.ok()) return change.error();
            if (before && small_pieces(b, tear.min_fragment_triangles) > small_before) {
                b = std::move(*before);
                // Each refusal cost a copy of the body: after a few the call waits for the next frame.
                if (++refusals == k_refusals_per_call) return std::optional<TopologyChange>{};
                continue;
            }
            strained.update(b, change.value());
            return std::optional<TopologyChange>(std::move(change).value());
        }
    }
    return std::optional<TopologyChange>{};
}

core::Result<std::optional<TopologyChange>> tear_once(sim::SoftBody& b, const TearOptions& tear, const CutOptions& cut_options) {
    PBDSPLAT_TRY(validate(tear));
    StrainedSet strained(b, tear.threshold, tear.gauge);
    return tear_once(b, tear, cut_options, strained);
}

} // namespace pbdsplat::topology
