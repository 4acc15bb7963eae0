#include "sim/crossings.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <tuple>
#include <vector>

#include "mesh/closest_point.h"

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

Corners corners_at(std::span<const Vec3f> points, const mesh::Triangle& t) {
    return {points[t[0]].cast<double>(), points[t[1]].cast<double>(), points[t[2]].cast<double>()};
}

// Every crossing pair of live triangles (indices into body.triangles) with corners at `points`
// (one per particle), passed to `on_cross`; pairs sharing a particle or a rest place, or refused
// by `consider`, are not tested. A triangle with a corner not finite (a body blown up) crosses
// nothing. Returns how many triangles were live.
template <class Consider, class OnCross>
size_t scan_crossings(const SoftBody& body, std::span<const Vec3f> points, const Consider& consider, const OnCross& on_cross) {
    const size_t n = body.particles.size();
    const bool rest_known = body.rest_positions.size() == n;
    std::vector<mesh::Triangle> live;
    std::vector<uint32_t> index;  // per live triangle, its index in body.triangles
    for (uint32_t t = 0; t < body.triangles.size(); ++t) {
        const mesh::Triangle& tri = body.triangles[t];
        if (tri[0] >= n || tri[1] >= n || tri[2] >= n || body.piece_of_particle[tri[0]] == k_no_piece) continue;
        if (!points[tri[0]].allFinite() || !points[tri[1]].allFinite() || !points[tri[2]].allFinite()) continue;
        live.push_back(tri), index.push_back(t);
    }
    if (live.size() < 2) return live.size();
    const mesh::TriangleGrid grid(points, live);
    const auto shares_a_place = [&](const mesh::Triangle& s, const mesh::Triangle& t) {
        for (uint32_t i : s)
            for (uint32_t j : t)
                if (i == j || (rest_known && body.rest_positions[i] == body.rest_positions[j])) return true;
        return false;
    };
    std::vector<uint32_t> near;
    for (uint32_t a = 0; a < live.size(); ++a) {
        // A triangle crossing this one has a point on it, so within its bounding sphere.
        Eigen::AlignedBox3f box(points[live[a][0]]);
        box.extend(points[live[a][1]]).extend(points[live[a][2]]);
        grid.near(box.center(), 0.5f * box.diagonal().norm(), near);
        const Corners s = corners_at(points, live[a]);
        for (const uint32_t b : near) {
            // Each pair once, from its smaller index.
            if (b <= a || !consider(live[a], live[b]) || shares_a_place(live[a], live[b])) continue;
            if (triangles_cross(s, corners_at(points, live[b]))) on_cross(index[a], index[b]);
        }
    }
    return live.size();
}

} // namespace

Crossings surface_crossings(const SoftBody& body) {
    Crossings out;
    const bool rest_known = body.rest_positions.size() == body.particles.size();
    std::vector<Vec3f> now(body.particles.size());
    for (size_t i = 0; i < now.size(); ++i) now[i] = xyz(body.particles.x[i]);
    std::vector<uint8_t> crossing(body.triangles.size(), 0);
    const auto any = [](const mesh::Triangle&, const mesh::Triangle&) { return true; };
    const size_t live = scan_crossings(body, now, any, [&](uint32_t a, uint32_t b) {
        const mesh::Triangle &s = body.triangles[a], &t = body.triangles[b];
        if (rest_known && triangles_cross(corners_at(body.rest_positions, s), corners_at(body.rest_positions, t))) return;
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
    const auto two_models = [&](const mesh::Triangle& s, const mesh::Triangle& t) {
        return body.model_of_particle[s[0]] != body.model_of_particle[t[0]];
    };
    scan_crossings(body, body.rest_positions, two_models, [&](uint32_t a, uint32_t b) {
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
