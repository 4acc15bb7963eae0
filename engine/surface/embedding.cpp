#include "surface/embedding.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "core/thread_pool.h"
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

// Of the candidates, the nearest triangle that faces the same way as the sample and reproduces
// it with coordinates inside (or just outside) the triangle: the sample's own part of the coarse
// surface, not the far side of a thin ear. UINT32_MAX: none reproduces it within `exact`.
std::pair<Solve, uint32_t> best_candidate(const SurfacePoint& sp, std::span<const mesh::ClosestPoint> cands, std::span<const Vec3f> rest,
                                          std::span<const mesh::Triangle> triangles, std::span<const Vec3f> rest_normals,
                                          const std::vector<Mat3f>& frames, float exact, float cell) {
    const Vec3f& p = sp.position;
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
        const float score = outside * 10.0f + std::abs(s.offset) / std::max(cell, 1e-12f);
        if (score < best_score) best_score = score, best = s, best_t = c.triangle;
        if (outside == 0.0f) break;  // the nearest containing one: good enough
    }
    return {best, best_t};
}

// p as the closest point of candidate c, offset along the interpolated normal there.
Solve along_normal(const Vec3f& p, const mesh::ClosestPoint& c, std::span<const Vec3f> rest, std::span<const mesh::Triangle> triangles,
                   std::span<const Vec3f> rest_normals) {
    const auto& tri = triangles[c.triangle];
    const Vec3f nb = rest_normals[tri[0]] + c.bary.x() * (rest_normals[tri[1]] - rest_normals[tri[0]]) +
                     c.bary.y() * (rest_normals[tri[2]] - rest_normals[tri[0]]);
    const Vec3f q = rest[tri[0]] + c.bary.x() * (rest[tri[1]] - rest[tri[0]]) + c.bary.y() * (rest[tri[2]] - rest[tri[0]]);
    Solve s{c.bary, nb.squaredNorm() > 0.0f ? (p - q).dot(nb) / nb.squaredNorm() : 0.0f, 0.0f};
    s.residual = (q + s.offset * nb - p).norm();
    return s;
}

struct EmbedContext {
    std::span<const Vec3f> rest;
    std::span<const mesh::Triangle> triangles;
    std::span<const Vec3f> rest_normals;
    const std::vector<Mat3f>& frames;
    const mesh::TriangleGrid& grid;
    float exact;
};

// Embeds one point: triangle, coordinates, offset and rest normal, counted in `st`.
void embed_one(const EmbedContext& x, const SurfacePoint& sp, std::vector<mesh::ClosestPoint>& cands, uint32_t& triangle,
               Vec2f& bary, float& offset, Vec3f& local_normal, EmbeddingStats& st) {
    const Vec3f& p = sp.position;
    // The nearest triangle and its rivals up to half as far again: on a thin part the
    // nearest may be the far side's.
    x.grid.closest(p, 1.5f, 0.25f * x.grid.cell_size(), cands);
    const auto [found, found_t] =
        best_candidate(sp, cands, x.rest, x.triangles, x.rest_normals, x.frames, x.exact, x.grid.cell_size());
    Solve best = found;
    uint32_t best_t = found_t;
    if (best_t == UINT32_MAX) {
        // Nothing reproduces it (a sample beyond every triangle's normal field): the closest
        // point, offset along the face normal.
        ++st.fallback;
        best = along_normal(p, cands.front(), x.rest, x.triangles, x.rest_normals);
        best_t = cands.front().triangle;
    }
    const bool outside = best.bary.minCoeff() < 0.0f || best.bary.sum() > 1.0f;
    st.outside += outside ? 1 : 0;
    st.max_rest_error = std::max(st.max_rest_error, best.residual);
    st.max_offset = std::max(st.max_offset, std::abs(best.offset));
    triangle = best_t;
    bary = best.bary;
    offset = best.offset;
    const auto& tri = x.triangles[best_t];
    const Vec2f& b = best.bary;
    const Vec3f interpolated = (1.0f - b.x() - b.y()) * x.rest_normals[tri[0]] + b.x() * x.rest_normals[tri[1]] +
                               b.y() * x.rest_normals[tri[2]];
    const Mat3f frame = surface_frame(x.rest[tri[0]], x.rest[tri[1]], x.rest[tri[2]], interpolated);
    local_normal = frame.transpose() * sp.normal;
}
} // namespace

void embed_points(std::span<const SurfacePoint> points, std::span<const Vec3f> rest, std::span<const mesh::Triangle> triangles,
                  std::span<const Vec3f> rest_normals, BoundaryParticles& out, EmbeddingStats* stats, core::ThreadPool* pool) {
    const mesh::TriangleGrid grid(rest, triangles);
    // Exact means: a few float roundings of the mesh's size.
    Eigen::AlignedBox3f box;
    for (const Vec3f& v : rest) box.extend(v);
    const float exact = 2e-6f * std::max(box.diagonal().norm(), 1e-12f);
    std::vector<Mat3f> frames(triangles.size());
    for (size_t t = 0; t < triangles.size(); ++t)
        frames[t] = triangle_frame(rest[triangles[t][0]], rest[triangles[t][1]], rest[triangles[t][2]]);
    const EmbedContext x{rest, triangles, rest_normals, frames, grid, exact};

    // Each point on its own: the arrays are sized first and written per index, so a pool's
    // chunks give the same result as one thread; the counts are summed per chunk in order.
    const size_t first = out.size(), n = points.size();
    out.offset.resize(first, 0.0f);
    out.local_normal.resize(first, Vec3f::UnitZ());
    out.triangle.resize(first + n);
    out.bary.resize(first + n);
    out.offset.resize(first + n);
    out.local_normal.resize(first + n);
    out.position.resize(first + n);
    out.normal.resize(first + n);
    const unsigned chunks = pool ? pool->chunks() : 1u;
    std::vector<EmbeddingStats> per_chunk(chunks);
    const auto run = [&](unsigned chunk, size_t b, size_t e) {
        std::vector<mesh::ClosestPoint> cands;
        for (size_t i = b; i < e; ++i) {
            const size_t o = first + i;
            embed_one(x, points[i], cands, out.triangle[o], out.bary[o], out.offset[o], out.local_normal[o], per_chunk[chunk]);
            out.position[o] = points[i].position;
            out.normal[o] = points[i].normal;
        }
    };
    if (pool) pool->parallel_for(n, run);
    else run(0, 0, n);
    EmbeddingStats st;
    for (const EmbeddingStats& c : per_chunk) {
        st.outside += c.outside;
        st.fallback += c.fallback;
        st.max_rest_error = std::max(st.max_rest_error, c.max_rest_error);
        st.max_offset = std::max(st.max_offset, c.max_offset);
    }
    st.samples = n;
    if (stats) *stats = st;
}

namespace {
// The three nearest of `count` samples in barycentric space (ties: the earlier first), their
// offsets and rest normals inverse-distance weighted. One routine for both entry points, so they
// give the same numbers.
template <class Bary, class Offset, class Normal>
void blend_nearest(size_t count, const Bary& bary_of, const Offset& offset_of, const Normal& normal_of, const Vec2f& bary,
                   float& offset, Vec3f& local_normal) {
    // The three nearest: enough to follow the fine surface's slope across the gap, few enough
    // that a far sample on the other side of a fold does not pull the new one off the surface.
    // Kept in three named slots (an insertion into a small array cost a third of the density
    // control's darts on the bunny).
    constexpr float inf = std::numeric_limits<float>::infinity();
    float d0 = inf, d1 = inf, d2 = inf;
    size_t i0 = 0, i1 = 0, i2 = 0;
    for (size_t k = 0; k < count; ++k) {
        const float d = (bary_of(k) - bary).squaredNorm();
        if (d >= d2) continue;
        if (d1 > d) {
            d2 = d1, i2 = i1;
            if (d0 > d) d1 = d0, i1 = i0, d0 = d, i0 = k;
            else d1 = d, i1 = k;
        } else {
            d2 = d, i2 = k;
        }
    }
    const float dist[3] = {d0, d1, d2};
    const size_t index[3] = {i0, i1, i2};
    float wsum = 0.0f, sum = 0.0f;
    Vec3f n = Vec3f::Zero();
    for (int m = 0; m < 3; ++m) {
        if (!std::isfinite(dist[m])) break;
        const float w = 1.0f / (dist[m] + 1e-8f);
        wsum += w;
        sum += w * offset_of(index[m]);
        n += w * normal_of(index[m]);
    }
    offset = sum / wsum;
    if (n.norm() > 1e-6f) local_normal = n.normalized();
}
} // namespace

void interpolate_embedding(const BoundaryParticles& s, std::span<const uint32_t> same, const Vec2f& bary, float& offset,
                           Vec3f& local_normal) {
    offset = 0.0f;
    local_normal = Vec3f::UnitZ();
    if (same.empty() || !s.embedded()) return;
    blend_nearest(
        same.size(), [&](size_t k) -> const Vec2f& { return s.bary[same[k]]; }, [&](size_t k) { return s.offset[same[k]]; },
        [&](size_t k) -> const Vec3f& { return s.local_normal[same[k]]; }, bary, offset, local_normal);
}

void EmbeddedNeighbours::assign(const BoundaryParticles& s, std::span<const uint32_t> same) {
    bary.clear(), offset.clear(), local_normal.clear();
    if (!s.embedded()) return;
    for (uint32_t i : same) bary.push_back(s.bary[i]), offset.push_back(s.offset[i]), local_normal.push_back(s.local_normal[i]);
}

void interpolate_embedding(const EmbeddedNeighbours& same, const Vec2f& bary, float& offset, Vec3f& local_normal) {
    offset = 0.0f;
    local_normal = Vec3f::UnitZ();
    if (same.bary.empty()) return;
    blend_nearest(
        same.bary.size(), [&](size_t k) -> const Vec2f& { return same.bary[k]; }, [&](size_t k) { return same.offset[k]; },
        [&](size_t k) -> const Vec3f& { return same.local_normal[k]; }, bary, offset, local_normal);
}

} // namespace pbdsplat::surface
