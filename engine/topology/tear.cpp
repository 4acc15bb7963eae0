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
    return core::Status::success();
}

std::vector<StrainedEdge> strained_edges(const sim::SoftBody& b, float threshold, size_t limit) {
    std::vector<StrainedEdge> strained;
    for (const sim::DistanceConstraint& c : b.distance) {
        if (!(c.rest > 0.0f)) continue;
        const float ratio = (b.particles.x[c.i] - b.particles.x[c.j]).head<3>().norm() / c.rest;
        if (ratio > threshold) strained.push_back({c.i, c.j, ratio});
    }
    const size_t n = std::min(strained.size(), limit);
    std::partial_sort(strained.begin(), strained.begin() + ptrdiff_t(n), strained.end(),
                      [](const StrainedEdge& x, const StrainedEdge& y) { return x.ratio > y.ratio || (x.ratio == y.ratio && x.i < y.i); });
    strained.resize(n);
    return strained;
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
} // namespace

core::Result<std::optional<TopologyChange>> tear_once(sim::SoftBody& b, const TearOptions& tear, const CutOptions& cut_options) {
    PBDSPLAT_TRY(validate(tear));
    // The most strained edges first; the first that can open does.
    for (const StrainedEdge& e : strained_edges(b, tear.threshold, 16)) {
        const Vec3f xi = sim::xyz(b.particles.x[e.i]), xj = sim::xyz(b.particles.x[e.j]);
        const Vec3f along = (xj - xi).normalized();
        // Split an end vertex across the edge: the plane through it, normal to the edge. Its fan
        // parts into the side that keeps the edge and the side that pulled it long.
        for (uint32_t v : {e.i, e.j}) {
            float radius = 0.0f;
            if (!splits_ring(b, v, along, radius)) continue;
            CutSurface slit = local_cut(sim::xyz(b.particles.x[v]), along, std::max(tear.reach * (xj - xi).norm(), 1.01f * radius));
            slit.particles = neighbourhood(b, v, 2);
            auto change = cut(b, slit, cut_options);
            if (!change.ok()) return change.error();
            return std::optional<TopologyChange>(std::move(change).value());
        }
    }
    return std::optional<TopologyChange>{};
}

} // namespace pbdsplat::topology
