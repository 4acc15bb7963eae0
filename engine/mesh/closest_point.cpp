#include "mesh/closest_point.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pbdsplat::mesh {

Vec2f closest_point_barycentric(const Vec3f& p, const Vec3f& a, const Vec3f& b, const Vec3f& c) {
    // Voronoi regions of the vertices, then the edges, then the face (Ericson, Real-Time
    // Collision Detection, 5.1.5), returning weights instead of the point.
    const Vec3f ab = b - a, ac = c - a, ap = p - a;
    const float d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0.0f && d2 <= 0.0f) return {0.0f, 0.0f};
    const Vec3f bp = p - b;
    const float d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0.0f && d4 <= d3) return {1.0f, 0.0f};
    const float vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) return {d1 / (d1 - d3), 0.0f};
    const Vec3f cp = p - c;
    const float d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0.0f && d5 <= d6) return {0.0f, 1.0f};
    const float vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) return {0.0f, d2 / (d2 - d6)};
    const float va = d3 * d6 - d5 * d4;
    if (va <= 0.0f && (d4 - d3) >= 0.0f && (d5 - d6) >= 0.0f) {
        const float w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return {1.0f - w, w};
    }
    const float denom = 1.0f / (va + vb + vc);
    return {vb * denom, vc * denom};
}

TriangleGrid::TriangleGrid(std::span<const Vec3f> positions, std::span<const Triangle> triangles)
    : positions_(positions), triangles_(triangles) {
    Eigen::AlignedBox3f box;
    double extent = 0.0;
    for (const Triangle& t : triangles) {
        Eigen::AlignedBox3f tb;
        for (uint32_t v : t) tb.extend(positions[v]);
        box.extend(tb);
        extent += double(tb.sizes().maxCoeff());
    }
    if (triangles.empty()) return;
    cell_ = std::max(float(extent / double(triangles.size())), 1e-6f * std::max(1e-6f, box.sizes().maxCoeff()));
    // Bound the cell count: a few cells per triangle are plenty.
    while (double((box.sizes() / cell_).array().ceil().prod()) > 8.0 * double(triangles.size()) + 64.0) cell_ *= 1.25f;
    origin_ = box.min();
    dims_ = ((box.sizes() / cell_).array().floor().cast<int>() + 1).max(1);
    const size_t cells = size_t(dims_.x()) * size_t(dims_.y()) * size_t(dims_.z());
    std::vector<uint32_t> count(cells + 1, 0);
    auto for_cells = [&](const Triangle& t, auto&& fn) {
        Eigen::AlignedBox3f tb;
        for (uint32_t v : t) tb.extend(positions[v]);
        const Eigen::Vector3i lo = cell_of(tb.min()), hi = cell_of(tb.max());
        for (int z = lo.z(); z <= hi.z(); ++z)
            for (int y = lo.y(); y <= hi.y(); ++y)
                for (int x = lo.x(); x <= hi.x(); ++x) fn((size_t(z) * size_t(dims_.y()) + size_t(y)) * size_t(dims_.x()) + size_t(x));
    };
    lowest_cell_.resize(triangles.size());
    spheres_.resize(triangles.size());
    for (uint32_t i = 0; i < triangles.size(); ++i) {
        Eigen::AlignedBox3f tb;
        for (uint32_t v : triangles[i]) tb.extend(positions[v]);
        lowest_cell_[i] = cell_of(tb.min());
        const Vec3f centre = tb.center();
        float radius = 0.0f;
        for (uint32_t v : triangles[i]) radius = std::max(radius, (positions[v] - centre).norm());
        spheres_[i] = Vec4f(centre.x(), centre.y(), centre.z(), radius);
    }
    for (const Triangle& t : triangles) for_cells(t, [&](size_t c) { ++count[c + 1]; });
    for (size_t c = 0; c < cells; ++c) count[c + 1] += count[c];
    start_ = count;
    items_.resize(count.back());
    for (uint32_t i = 0; i < triangles.size(); ++i) for_cells(triangles[i], [&](size_t c) { items_[count[c]++] = i; });
}

Eigen::Vector3i TriangleGrid::cell_of(const Vec3f& p) const {
    // Clamped before the conversion: a point far outside would overflow an int.
    const Eigen::Array3f top = (dims_ - Eigen::Vector3i::Ones()).cast<float>().array();
    return ((p - origin_) / cell_).array().floor().max(0.0f).min(top).cast<int>();
}

void TriangleGrid::near(const Vec3f& p, float radius, std::vector<uint32_t>& out) const {
    out.clear();
    if (triangles_.empty()) return;
    const Eigen::Vector3i lo = cell_of(p - Vec3f::Constant(radius)), hi = cell_of(p + Vec3f::Constant(radius));
    // A triangle over several cells is listed in each; it is taken from the first of them the
    // scan meets, the one at max(lo, its lowest cell) on each axis. No per-query marks, so
    // threads can share one grid.
    const auto first_here = [&](uint32_t t, int x, int y, int z) {
        const Eigen::Vector3i& m = lowest_cell_[t];
        return (x == lo.x() || x == m.x()) && (y == lo.y() || y == m.y()) && (z == lo.z() || z == m.z());
    };
    for (int z = lo.z(); z <= hi.z(); ++z)
        for (int y = lo.y(); y <= hi.y(); ++y)
            for (int x = lo.x(); x <= hi.x(); ++x) {
                const size_t c = (size_t(z) * size_t(dims_.y()) + size_t(y)) * size_t(dims_.x()) + size_t(x);
                for (uint32_t k = start_[c]; k < start_[c + 1]; ++k)
                    if (first_here(items_[k], x, y, z)) out.push_back(items_[k]);
            }
}

void TriangleGrid::closest(const Vec3f& p, float factor, float margin, std::vector<ClosestPoint>& out) const {
    out.clear();
    if (triangles_.empty()) return;
    thread_local std::vector<uint32_t> cand;  // scratch: embedding asks this for every sample
    if (!p.allFinite()) return;
    // At this radius every triangle is gathered: the farthest corner of the grid's box, and a cell.
    const Vec3f to_far = (p - origin_).cwiseAbs().cwiseMax((p - origin_ - dims_.cast<float>() * cell_).cwiseAbs());
    const float reach = to_far.norm() + cell_;
    for (float r = 0.5f * cell_;;) {
        near(p, r, cand);
        out.clear();
        float best = std::numeric_limits<float>::infinity();
        for (uint32_t t : cand) {
            // A triangle whose sphere lies past the band around the nearest so far would be
            // dropped below (the band only narrows): skipped before its closest point is solved.
            // The slack keeps rounding from dropping one the exact test would keep.
            const Vec4f& s = spheres_[t];
            const float band = factor * best + margin;
            if ((p - s.head<3>()).norm() - s.w() > band * 1.001f + 1e-5f * cell_) continue;
            const Triangle& tri = triangles_[t];
            const Vec3f &a = positions_[tri[0]], &b = positions_[tri[1]], &c = positions_[tri[2]];
            const Vec2f w = closest_point_barycentric(p, a, b, c);
            const float d = (a + w.x() * (b - a) + w.y() * (c - a) - p).norm();
            out.push_back({d, t, w});
            best = std::min(best, d);
        }
        // Everything within r was searched: done once the band we want fits inside it.
        const float wanted = factor * best + margin;
        if (wanted <= r || r >= reach) {
            std::erase_if(out, [&](const ClosestPoint& c) { return c.distance > wanted; });
            std::sort(out.begin(), out.end(), [](const ClosestPoint& x, const ClosestPoint& y) {
                return x.distance != y.distance ? x.distance < y.distance : x.triangle < y.triangle;
            });
            return;
        }
        // Nothing found yet (wanted is infinite): as far as the whole box at once.
        r = std::min(std::max(wanted, 2.0f * r), reach);
    }
}

float TriangleGrid::distance(const Vec3f& p) const {
    std::vector<ClosestPoint> c;
    closest(p, 1.0f, 0.0f, c);
    return c.empty() ? std::numeric_limits<float>::infinity() : c.front().distance;
}

} // namespace pbdsplat::mesh
