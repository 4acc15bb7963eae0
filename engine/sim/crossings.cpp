#include "sim/crossings.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <tuple>
#include <vector>

namespace pbdsplat::sim {
namespace {

using V3 = Eigen::Vector3d;
using Corners = std::array<V3, 3>;

double orient(const V3& a, const V3& b, const V3& c, const V3& d) { return (b - a).cross(c - a).dot(d - a); }

// Whether segment pq passes through the interior of triangle abc (touching or coplanar: no).
bool segment_crosses(const V3& p, const V3& q, const Corners& t) {
    const double sp = orient(t[0], t[1], t[2], p), sq = orient(t[0], t[1], t[2], q);
    if (!((sp > 0.0 && sq < 0.0) || (sp < 0.0 && sq > 0.0))) return false;
    const double u = orient(p, q, t[0], t[1]), v = orient(p, q, t[1], t[2]), w = orient(p, q, t[2], t[0]);
    return (u > 0.0 && v > 0.0 && w > 0.0) || (u < 0.0 && v < 0.0 && w < 0.0);
}

bool triangles_cross(const Corners& s, const Corners& t) {
    for (size_t k = 0; k < 3; ++k)
        if (segment_crosses(s[k], s[(k + 1) % 3], t) || segment_crosses(t[k], t[(k + 1) % 3], s)) return true;
    return false;
}

// Boxes in a hash grid of cells `cell` wide; a box over k_span cells on a side goes to a list
// that every box meets.
class BoxGrid {
public:
    BoxGrid(const std::vector<Eigen::AlignedBox3d>& boxes, double cell) : boxes_(boxes), cell_(cell) {
        table_ = std::bit_ceil(std::max<size_t>(64, 2 * boxes.size()));
        start_.assign(table_ + 1, 0);
        for (size_t k = 0; k < boxes.size(); ++k)
            if (!cells(boxes[k], [&](size_t c) { ++start_[c + 1]; })) wide_.push_back(uint32_t(k));
        for (size_t c = 0; c < table_; ++c) start_[c + 1] += start_[c];
        entries_.resize(start_.back());
        std::vector<uint32_t> cursor(start_.begin(), start_.end() - 1);
        for (size_t k = 0; k < boxes.size(); ++k) cells(boxes[k], [&](size_t c) { entries_[cursor[c]++] = uint32_t(k); });
    }
    // Every box index that may meet box a (some more than once), all of them where a is wide.
    template <class Fn>
    void near(uint32_t a, const Fn& fn) const {
        const bool placed = cells(boxes_[a], [&](size_t c) {
            for (uint32_t e = start_[c]; e < start_[c + 1]; ++e) fn(entries_[e]);
        });
        if (!placed)
            for (uint32_t b = 0; b < boxes_.size(); ++b) fn(b);
        for (uint32_t b : wide_) fn(b);
    }

private:
    static constexpr int k_span = 16;
    template <class Fn>
    bool cells(const Eigen::AlignedBox3d& b, const Fn& fn) const {
        // Far out (past int's reach in cells) a box is wide.
        constexpr double k_reach = 1e9;
        if (!((b.min().array() / cell_).abs() < k_reach).all() || !((b.max().array() / cell_).abs() < k_reach).all()) return false;
        const Eigen::Array3i lo = (b.min().array() / cell_).floor().cast<int>(), hi = (b.max().array() / cell_).floor().cast<int>();
        if (!((hi - lo) < k_span).all()) return false;
        for (int z = lo.z(); z <= hi.z(); ++z)
            for (int y = lo.y(); y <= hi.y(); ++y)
                for (int x = lo.x(); x <= hi.x(); ++x)
                    fn(size_t((uint64_t(int64_t(x)) * 73856093u) ^ (uint64_t(int64_t(y)) * 19349663u) ^ (uint64_t(int64_t(z)) * 83492791u)) &
                       (table_ - 1));
        return true;
    }
    const std::vector<Eigen::AlignedBox3d>& boxes_;
    double cell_;
    size_t table_ = 0;
    std::vector<uint32_t> start_, entries_, wide_;
};

// Every crossing pair of live triangles (indices into body.triangles) with corners from
// `corners`, passed to `on_cross`; pairs sharing a particle or a rest place, or refused by
// `consider`, are not tested.
template <class CornersOf, class Consider, class OnCross>
void scan_crossings(const SoftBody& body, const CornersOf& corners, const Consider& consider, const OnCross& on_cross) {
    const size_t n = body.particles.size();
    const bool rest_known = body.rest_positions.size() == n;
    std::vector<uint32_t> live;
    for (uint32_t t = 0; t < body.triangles.size(); ++t) {
        const mesh::Triangle& tri = body.triangles[t];
        if (tri[0] < n && tri[1] < n && tri[2] < n && body.piece_of_particle[tri[0]] != k_no_piece) live.push_back(t);
    }
    if (live.size() < 2) return;
    // A triangle with a corner not finite (a body blown up) crosses nothing; left in, its box
    // would meet every other.
    std::vector<Eigen::AlignedBox3d> box;
    box.reserve(live.size());
    double edges = 0.0;
    size_t kept = 0;
    for (const uint32_t t : live) {
        const Corners c = corners(body.triangles[t]);
        if (!c[0].allFinite() || !c[1].allFinite() || !c[2].allFinite()) continue;
        live[kept++] = t;
        box.emplace_back(c[0]);
        box.back().extend(c[1]).extend(c[2]);
        edges += (c[1] - c[0]).norm();
    }
    live.resize(kept);
    if (live.size() < 2) return;
    const BoxGrid grid(box, std::max(edges / double(live.size()), 1e-9));
    std::vector<uint32_t> seen(live.size(), UINT32_MAX);
    const auto shares_a_place = [&](const mesh::Triangle& s, const mesh::Triangle& t) {
        for (uint32_t i : s)
            for (uint32_t j : t)
                if (i == j || (rest_known && body.rest_positions[i] == body.rest_positions[j])) return true;
        return false;
    };
    for (uint32_t a = 0; a < live.size(); ++a) {
        // Each pair once, from its smaller index.
        grid.near(a, [&](uint32_t b) {
            if (b <= a || seen[b] == a) return;
            seen[b] = a;
            const mesh::Triangle &s = body.triangles[live[a]], &t = body.triangles[live[b]];
            if (!box[a].intersects(box[b]) || !consider(s, t) || shares_a_place(s, t) || !triangles_cross(corners(s), corners(t))) return;
            on_cross(live[a], live[b]);
        });
    }
}

} // namespace

Crossings surface_crossings(const SoftBody& body) {
    Crossings out;
    const size_t n = body.particles.size();
    const bool rest_known = body.rest_positions.size() == n;
    const auto now = [&](const mesh::Triangle& t) {
        const auto at = [&](uint32_t i) { return V3(body.particles.x[i].head<3>().cast<double>()); };
        return Corners{at(t[0]), at(t[1]), at(t[2])};
    };
    const auto rest = [&](const mesh::Triangle& t) {
        const auto at = [&](uint32_t i) { return V3(body.rest_positions[i].cast<double>()); };
        return Corners{at(t[0]), at(t[1]), at(t[2])};
    };
    std::vector<uint8_t> crossing(body.triangles.size(), 0);
    size_t live = 0;
    for (const mesh::Triangle& t : body.triangles)
        live += t[0] < n && t[1] < n && t[2] < n && body.piece_of_particle[t[0]] != k_no_piece;
    const auto any = [](const mesh::Triangle&, const mesh::Triangle&) { return true; };
    scan_crossings(body, now, any, [&](uint32_t a, uint32_t b) {
        const mesh::Triangle &s = body.triangles[a], &t = body.triangles[b];
        if (rest_known && triangles_cross(rest(s), rest(t))) return;
        crossing[a] = crossing[b] = 1;
        ++out.pairs;
        if (body.piece_of_particle[s[0]] == body.piece_of_particle[t[0]]) ++out.self_pairs;
    });
    out.triangles = size_t(std::count(crossing.begin(), crossing.end(), 1));
    out.ratio = live ? double(out.triangles) / double(live) : 0.0;
    return out;
}

std::vector<ModelOverlap> models_crossing_at_rest(const SoftBody& body) {
    std::vector<ModelOverlap> out;
    const size_t n = body.particles.size();
    if (body.rest_positions.size() != n || body.model_of_particle.size() != n) return out;
    const auto rest = [&](const mesh::Triangle& t) {
        const auto at = [&](uint32_t i) { return V3(body.rest_positions[i].cast<double>()); };
        return Corners{at(t[0]), at(t[1]), at(t[2])};
    };
    const auto two_models = [&](const mesh::Triangle& s, const mesh::Triangle& t) {
        return body.model_of_particle[s[0]] != body.model_of_particle[t[0]];
    };
    scan_crossings(body, rest, two_models, [&](uint32_t a, uint32_t b) {
        uint32_t ma = body.model_of_particle[body.triangles[a][0]], mb = body.model_of_particle[body.triangles[b][0]];
        if (ma > mb) std::swap(ma, mb);
        auto it = std::find_if(out.begin(), out.end(), [&](const ModelOverlap& o) { return o.a == ma && o.b == mb; });
        if (it == out.end()) out.push_back({ma, mb, 0}), it = out.end() - 1;
        ++it->pairs;
    });
    std::sort(out.begin(), out.end(), [](const ModelOverlap& x, const ModelOverlap& y) { return std::tie(x.a, x.b) < std::tie(y.a, y.b); });
    return out;
}

} // namespace pbdsplat::sim
