#include "surface/embedding.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "mesh/closest_point.h"

namespace pbdsplat::surface {
namespace {

struct Solve {
    Vec2f bary;
    float offset = 0.0f;
    float residual = 1e30f;
};

// Solves a + b1 (b - a) + b2 (c - a) + d N(b1, b2) = p for (b1, b2, d), N the unnormalised
// interpolation of the vertex normals: the runtime evaluates exactly this, so a converged
// solve reproduces p. Newton from the closest point; the system is bilinear and well
// conditioned while |d| stays below the triangle's curvature radius.
Solve solve(const Vec3f& p, const std::array<Vec3f, 3>& x, const std::array<Vec3f, 3>& n, Vec2f b, float d) {
    Solve s;
    for (int it = 0; it < 12; ++it) {
        const Vec3f nb = n[0] + b.x() * (n[1] - n[0]) + b.y() * (n[2] - n[0]);
        const Vec3f f = x[0] + b.x() * (x[1] - x[0]) + b.y() * (x[2] - x[0]) + d * nb - p;
        s = {b, d, f.norm()};
        Mat3f j;
        j.col(0) = (x[1] - x[0]) + d * (n[1] - n[0]);
        j.col(1) = (x[2] - x[0]) + d * (n[2] - n[0]);
        j.col(2) = nb;
        const Vec3f step = j.partialPivLu().solve(-f);
        if (!step.allFinite()) break;
        b += step.head<2>();
        d += step.z();
    }
    const Vec3f nb = n[0] + b.x() * (n[1] - n[0]) + b.y() * (n[2] - n[0]);
    const float r = (x[0] + b.x() * (x[1] - x[0]) + b.y() * (x[2] - x[0]) + d * nb - p).norm();
    if (std::isfinite(r) && r < s.residual) s = {b, d, r};
    return s;
}

} // namespace

void embed_points(std::span<const SurfacePoint> points, std::span<const Vec3f> rest, std::span<const mesh::Triangle> triangles,
                  std::span<const Vec3f> rest_normals, BoundaryParticles& out, EmbeddingStats* stats) {
    EmbeddingStats st;
    const mesh::TriangleGrid grid(rest, triangles);
    // Exact means: a few float roundings of the mesh's size.
    Eigen::AlignedBox3f box;
    for (const Vec3f& v : rest) box.extend(v);
    const float exact = 2e-6f * std::max(box.diagonal().norm(), 1e-12f);
    std::vector<Mat3f> frames(triangles.size());
    for (size_t t = 0; t < triangles.size(); ++t)
        frames[t] = triangle_frame(rest[triangles[t][0]], rest[triangles[t][1]], rest[triangles[t][2]]);

    std::vector<mesh::ClosestPoint> cands;
    const size_t first = out.size();
    out.offset.resize(first, 0.0f);
    out.local_normal.resize(first, Vec3f::UnitZ());
    for (const SurfacePoint& sp : points) {
        const Vec3f& p = sp.position;
        // The nearest triangle and its rivals up to half as far again: on a thin part the
        // nearest may be the far side's.
        grid.closest(p, 1.5f, 0.25f * grid.cell_size(), cands);
        // The nearest triangle that faces the same way as the sample and reproduces it with
        // coordinates inside (or just outside) the triangle: the sample's own part of the
        // coarse surface, not the far side of a thin ear.
        Solve best;
        uint32_t best_t = UINT32_MAX;
        float best_score = 1e30f;
        for (const mesh::ClosestPoint& c : cands) {
            const auto& tri = triangles[c.triangle];
            if (frames[c.triangle].col(2).dot(sp.normal) < -0.2f) continue;
            const std::array<Vec3f, 3> x{rest[tri[0]], rest[tri[1]], rest[tri[2]]};
            const std::array<Vec3f, 3> n{rest_normals[tri[0]], rest_normals[tri[1]], rest_normals[tri[2]]};
            const Vec3f nb = n[0] + c.bary.x() * (n[1] - n[0]) + c.bary.y() * (n[2] - n[0]);
            const Vec3f q = x[0] + c.bary.x() * (x[1] - x[0]) + c.bary.y() * (x[2] - x[0]);
            const float d0 = nb.squaredNorm() > 0.0f ? (p - q).dot(nb) / nb.squaredNorm() : 0.0f;
            const Solve s = solve(p, x, n, c.bary, d0);
            if (!(s.residual <= exact)) continue;
            const float outside = std::max({0.0f, -s.bary.x(), -s.bary.y(), s.bary.x() + s.bary.y() - 1.0f});
            const float score = outside * 10.0f + std::abs(s.offset) / std::max(grid.cell_size(), 1e-12f);
            if (score < best_score) best_score = score, best = s, best_t = c.triangle;
            if (outside == 0.0f) break;  // the nearest containing one: good enough
        }
        if (best_t == UINT32_MAX) {
            // Nothing reproduces it (a sample beyond every triangle's normal field): the closest
            // point, offset along the face normal.
            ++st.fallback;
            const mesh::ClosestPoint& c = cands.front();
            const auto& tri = triangles[c.triangle];
            const Vec3f nb = rest_normals[tri[0]] + c.bary.x() * (rest_normals[tri[1]] - rest_normals[tri[0]]) +
                             c.bary.y() * (rest_normals[tri[2]] - rest_normals[tri[0]]);
            const Vec3f q = rest[tri[0]] + c.bary.x() * (rest[tri[1]] - rest[tri[0]]) + c.bary.y() * (rest[tri[2]] - rest[tri[0]]);
            best = {c.bary, nb.squaredNorm() > 0.0f ? (p - q).dot(nb) / nb.squaredNorm() : 0.0f, 0.0f};
            best_t = c.triangle;
            const Vec3f e = q + best.offset * nb - p;
            best.residual = e.norm();
        }
        const bool outside = best.bary.minCoeff() < 0.0f || best.bary.sum() > 1.0f;
        st.outside += outside ? 1 : 0;
        st.max_rest_error = std::max(st.max_rest_error, best.residual);
        st.max_offset = std::max(st.max_offset, std::abs(best.offset));
        out.triangle.push_back(best_t);
        out.bary.push_back(best.bary);
        out.offset.push_back(best.offset);
        {
            const auto& tri = triangles[best_t];
            const Vec2f& b = best.bary;
            const Vec3f interpolated = (1.0f - b.x() - b.y()) * rest_normals[tri[0]] + b.x() * rest_normals[tri[1]] +
                                       b.y() * rest_normals[tri[2]];
            const Mat3f frame = surface_frame(rest[tri[0]], rest[tri[1]], rest[tri[2]], interpolated);
            out.local_normal.push_back(frame.transpose() * sp.normal);
        }
        out.position.push_back(p);
        out.normal.push_back(sp.normal);
    }
    st.samples = points.size();
    if (stats) *stats = st;
}

void interpolate_embedding(const BoundaryParticles& s, std::span<const uint32_t> same, const Vec2f& bary, float& offset,
                           Vec3f& local_normal) {
    offset = 0.0f;
    local_normal = Vec3f::UnitZ();
    if (same.empty() || !s.embedded()) return;
    // The three nearest: enough to follow the fine surface's slope across the gap, few enough
    // that a far sample on the other side of a fold does not pull the new one off the surface.
    constexpr int k = 3;
    std::array<std::pair<float, uint32_t>, k> best;
    best.fill({std::numeric_limits<float>::infinity(), 0u});
    for (uint32_t i : same) {
        const float d2 = (s.bary[i] - bary).squaredNorm();
        if (d2 >= best[k - 1].first) continue;
        int j = k - 1;
        while (j > 0 && best[j - 1].first > d2) best[j] = best[j - 1], --j;
        best[j] = {d2, i};
    }
    float wsum = 0.0f, d = 0.0f;
    Vec3f n = Vec3f::Zero();
    for (const auto& [d2, i] : best) {
        if (!std::isfinite(d2)) break;
        const float w = 1.0f / (d2 + 1e-8f);
        wsum += w;
        d += w * s.offset[i];
        n += w * s.local_normal[i];
    }
    offset = d / wsum;
    if (n.norm() > 1e-6f) local_normal = n.normalized();
}

} // namespace pbdsplat::surface
