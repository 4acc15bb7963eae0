#include "mesh/polygon.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pbdsplat::mesh {
namespace {

float cross2(const Vec2f& a, const Vec2f& b, const Vec2f& c) {
    return (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
}

// p inside or on triangle (a, b, c), which is counter-clockwise.
bool inside(const Vec2f& p, const Vec2f& a, const Vec2f& b, const Vec2f& c) {
    return cross2(a, b, p) >= 0.0f && cross2(b, c, p) >= 0.0f && cross2(c, a, p) >= 0.0f;
}

constexpr size_t k_max_clipped_corners = 4096;

void fan(size_t n, std::vector<std::array<uint32_t, 3>>& out) {
    for (uint32_t k = 1; k + 1 < n; ++k) out.push_back({0, k, k + 1});
}

// A quad: the shorter diagonal (the split most exporters and loaders make), unless the quad is
// concave there: then the other one, which is inside. `p`: the corners in the plane.
std::vector<std::array<uint32_t, 3>> split_quad(std::span<const Vec3f> corners, const std::vector<Vec2f>& p) {
    const bool short02 = (corners[2] - corners[0]).squaredNorm() < (corners[3] - corners[1]).squaredNorm();
    const bool ok02 = cross2(p[0], p[1], p[2]) > 0.0f && cross2(p[0], p[2], p[3]) > 0.0f;
    const bool ok13 = cross2(p[0], p[1], p[3]) > 0.0f && cross2(p[1], p[2], p[3]) > 0.0f;
    if ((short02 && ok02) || (!ok13 && !short02 && ok02) || (!ok02 && !ok13 && short02)) return {{0, 1, 2}, {0, 2, 3}};
    return {{0, 1, 3}, {1, 2, 3}};
}

// Ear clipping of a counter-clockwise outline in the plane; what no ear can be clipped from
// (a self-intersecting or degenerate rest) is closed as a fan.
void clip_ears(const std::vector<Vec2f>& p, std::vector<std::array<uint32_t, 3>>& out) {
    const size_t n = p.size();
    std::vector<uint32_t> ring(n);
    for (uint32_t i = 0; i < n; ++i) ring[i] = i;
    size_t guard = 0;
    while (ring.size() > 3 && guard < n * n) {
        ++guard;
        bool clipped = false;
        const size_t m = ring.size();
        for (size_t i = 0; i < m && !clipped; ++i) {
            const uint32_t a = ring[(i + m - 1) % m], b = ring[i], c = ring[(i + 1) % m];
            if (cross2(p[a], p[b], p[c]) <= 0.0f) continue;  // reflex or flat: not an ear
            bool empty = true;
            for (uint32_t k : ring) {
                if (k == a || k == b || k == c) continue;
                // A bridge edge repeats positions: a corner on the ear's own corner does not block it.
                if (p[k] == p[a] || p[k] == p[b] || p[k] == p[c]) continue;
                if (inside(p[k], p[a], p[b], p[c])) {
                    empty = false;
                    break;
                }
            }
            if (!empty) continue;
            out.push_back({a, b, c});
            ring.erase(ring.begin() + std::ptrdiff_t(i));
            clipped = true;
        }
        if (!clipped) break;
    }
    if (ring.size() == 3) {
        out.push_back({ring[0], ring[1], ring[2]});
        return;
    }
    for (size_t k = 1; k + 1 < ring.size(); ++k) out.push_back({ring[0], ring[k], ring[k + 1]});
}

} // namespace

std::vector<std::array<uint32_t, 3>> triangulate_polygon(std::span<const Vec3f> corners) {
    std::vector<std::array<uint32_t, 3>> out;
    const size_t n = corners.size();
    if (n < 3) return out;
    if (n == 3) return {{0, 1, 2}};
    // Ear clipping is quadratic in the corners: a face of thousands (a file that writes a whole
    // outline as one face) is split as a fan rather than stalling the load.
    if (n > k_max_clipped_corners) {
        fan(n, out);
        return out;
    }
    // Newell's normal: the plane the outline winds about, robust to concave corners.
    Vec3f normal = Vec3f::Zero();
    for (size_t i = 0; i < n; ++i) {
        const Vec3f& a = corners[i];
        const Vec3f& b = corners[(i + 1) % n];
        normal += Vec3f((a.y() - b.y()) * (a.z() + b.z()), (a.z() - b.z()) * (a.x() + b.x()), (a.x() - b.x()) * (a.y() + b.y()));
    }
    if (!(normal.norm() > 0.0f) || !std::isfinite(normal.norm())) {
        fan(n, out);
        return out;
    }
    normal.normalize();
    const Vec3f u = (std::abs(normal.x()) < 0.9f ? Vec3f::UnitX() : Vec3f::UnitY()).cross(normal).normalized();
    const Vec3f v = normal.cross(u);
    std::vector<Vec2f> p(n);
    for (size_t i = 0; i < n; ++i) p[i] = Vec2f(corners[i].dot(u), corners[i].dot(v));
    if (n == 4) return split_quad(corners, p);
    // (u, v, normal) is right-handed, so the outline runs counter-clockwise in (u, v).
    clip_ears(p, out);
    return out;
}

std::vector<std::array<uint32_t, 3>> triangulate_least_area(std::span<const Vec3f> corners) {
    const size_t n = corners.size();
    if (n < 3) return {};
    if (n == 3) return {{0, 1, 2}};
    if (n > k_max_least_area_corners) return triangulate_polygon(corners);
    // area[i * n + j]: the least area spanning corners i..j closed by the chord (i, j); split: the
    // third corner of the triangle on that chord.
    std::vector<double> area(n * n, 0.0);
    std::vector<uint16_t> split(n * n, 0);
    for (size_t len = 2; len < n; ++len)
        for (size_t i = 0; i + len < n; ++i) {
            const size_t j = i + len;
            double best = std::numeric_limits<double>::infinity();
            size_t best_k = i + 1;
            const Vec3d a = corners[i].cast<double>(), c = corners[j].cast<double>();
            for (size_t k = i + 1; k < j; ++k) {
                const double t = 0.5 * (corners[k].cast<double>() - a).cross(c - a).norm();
                const double sum = area[i * n + k] + area[k * n + j] + t;
                if (sum < best) best = sum, best_k = k;
            }
            area[i * n + j] = best;
            split[i * n + j] = uint16_t(best_k);
        }
    std::vector<std::array<uint32_t, 3>> out;
    out.reserve(n - 2);
    std::vector<std::pair<size_t, size_t>> pending{{0, n - 1}};
    while (!pending.empty()) {
        const auto [i, j] = pending.back();
        pending.pop_back();
        if (j - i < 2) continue;
        const size_t k = split[i * n + j];
        out.push_back({uint32_t(i), uint32_t(k), uint32_t(j)});
        pending.push_back({i, k}), pending.push_back({k, j});
    }
    return out;
}

namespace {
// The ends of the chord closing a run of older corners (`run`, indices into `corners`): the new
// corners before and after it (`first`, `last`), or, where the cut went through a corner of the
// older rim (whose index the older side kept), that corner: the new corner beyond it then lies
// off the run's plane.
void chord_ends(std::span<const Vec3f> corners, const std::vector<uint32_t>& run, size_t& first, size_t& last) {
    if (run.size() < 3) return;
    Vec3f normal = Vec3f::Zero(), centre = Vec3f::Zero();
    for (size_t q = 0; q < run.size(); ++q) {
        normal += corners[run[q]].cross(corners[run[(q + 1) % run.size()]]);
        centre += corners[run[q]];
    }
    centre /= float(run.size());
    if (!(normal.norm() > 0.0f)) return;
    normal.normalize();
    const auto off_plane = [&](size_t c, size_t inner) {
        return std::abs((corners[c] - centre).dot(normal)) > 0.25f * (corners[c] - corners[inner]).norm();
    };
    if (off_plane(first, run.front())) first = run.front();
    if (off_plane(last, run.back())) last = run.back();
}
} // namespace

std::vector<std::array<uint32_t, 3>> triangulate_across_older(std::span<const Vec3f> corners, std::span<const uint8_t> older,
                                                              std::vector<uint8_t>* parts) {
    const size_t n = corners.size();
    const auto fresh = std::find(older.begin(), older.end(), uint8_t(0));
    if (older.size() != n || fresh == older.end() || std::find(older.begin(), older.end(), uint8_t(1)) == older.end()) {
        std::vector<std::array<uint32_t, 3>> out = triangulate_least_area(corners);
        if (parts) parts->assign(out.size(), 0);
        return out;
    }
    std::vector<std::array<uint32_t, 3>> out;
    std::vector<uint32_t> part;  // corners of one part, as indices into `corners`
    std::vector<Vec3f> outline;
    const auto span_part = [&] {
        if (part.size() < 3) return;
        outline.clear();
        for (uint32_t k : part) outline.push_back(corners[k]);
        for (const std::array<uint32_t, 3>& t : triangulate_least_area(outline)) out.push_back({part[t[0]], part[t[1]], part[t[2]]});
    };
    std::vector<uint8_t> inside_run(n, 0);  // strictly between a run's chord ends
    // Walk from a new corner. A run of older corners spans the older face's part, closed by the
    // chord between the corners where the cut crossed the older rim (chord_ends).
    const size_t start = size_t(fresh - older.begin());
    size_t runs = 0;
    for (size_t step = 0; step < n; ++step) {
        const size_t k = (start + step) % n;
        if (!older[k] || older[(k + n - 1) % n]) continue;
        size_t j = k;
        part.clear();
        while (older[j]) part.push_back(uint32_t(j)), j = (j + 1) % n;
        size_t first = (k + n - 1) % n, last = j;
        chord_ends(corners, part, first, last);
        part.clear();
        for (size_t q = first;; q = (q + 1) % n) {
            part.push_back(uint32_t(q));
            if (q == last) break;
            if (q != first) inside_run[q] = 1;
        }
        span_part();
        if (parts) parts->resize(out.size(), uint8_t(std::min<size_t>(++runs, 255)));
    }
    // The rest (the new corners and the chords' ends) spans the cut's part.
    part.clear();
    for (size_t step = 0; step < n; ++step) {
        const size_t k = (start + step) % n;
        if (!inside_run[k]) part.push_back(uint32_t(k));
    }
    span_part();
    if (parts) parts->resize(out.size(), 0);
    return out;
}

} // namespace pbdsplat::mesh
