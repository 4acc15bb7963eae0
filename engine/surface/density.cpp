#include "surface/density.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "core/assert.h"
#include "mesh/deformation.h"
#include "surface/embedding.h"
#include "surface/point_grid.h"

namespace pbdsplat::surface {
namespace {

// Index lists by key (compressed rows): keys [0, n), values in insertion order.
struct Rows {
    std::vector<uint32_t> start, items;
    std::span<const uint32_t> operator[](uint32_t k) const { return {items.data() + start[k], items.data() + start[k + 1]}; }
};
template <class KeyOf>
Rows make_rows(size_t keys, size_t count, const KeyOf& key_of) {
    Rows r;
    r.start.assign(keys + 1, 0);
    for (size_t i = 0; i < count; ++i) ++r.start[key_of(i) + 1];
    for (size_t k = 0; k < keys; ++k) r.start[k + 1] += r.start[k];
    r.items.resize(r.start.back());
    std::vector<uint32_t> fill(r.start.begin(), r.start.end() - 1);
    for (size_t i = 0; i < count; ++i) r.items[fill[key_of(i)]++] = uint32_t(i);
    return r;
}

struct Work {
    float priority;
    uint32_t triangle;
    bool grow;
};

} // namespace

DensityControl::DensityControl(std::span<const Vec3f> rest, std::span<const mesh::Triangle> triangles, const DensityOptions& o)
    : options_(o) {
    inverse_rest_.resize(triangles.size());
    for (uint32_t t = 0; t < triangles.size(); ++t) set_rest(rest, triangles, t);
    stretch_.assign(triangles.size(), 1.0f);
    reference_.assign(triangles.size(), 1.0f);
    beyond_.assign(triangles.size(), 0);
}

void DensityControl::set_rest(std::span<const Vec3f> rest, std::span<const mesh::Triangle> triangles, uint32_t t) {
    // A sliver (zero inverse) is never resampled: its neighbours cover it.
    inverse_rest_[t] = mesh::rest_frame_inverse(rest[triangles[t][0]], rest[triangles[t][1]], rest[triangles[t][2]]);
}

void DensityControl::topology_changed(std::span<const Vec3f> rest, std::span<const mesh::Triangle> triangles,
                                      std::span<const uint32_t> touched) {
    inverse_rest_.resize(triangles.size(), Eigen::Matrix2f::Zero());
    stretch_.resize(triangles.size(), 1.0f);
    reference_.resize(triangles.size(), 1.0f);
    beyond_.resize(triangles.size(), 0);
    // A touched triangle was refilled from its rest shape: its samples stand for stretch 1.
    for (uint32_t t : touched) {
        set_rest(rest, triangles, t);
        reference_[t] = 1.0f;
        beyond_[t] = 0;
    }
}

DensityStats DensityControl::update(std::span<const Vec4f> x, std::span<const Vec3f> normals,
                                    std::span<const mesh::Triangle> triangles, bool anchors_drawn, float h, uint32_t seed,
                                    BoundaryParticles& s) {
    PBDSPLAT_ASSERT(triangles.size() == inverse_rest_.size(),
                    "density control: the triangle list changed size; call topology_changed() after every topology change");
    DensityStats stats;
    ++frame_;
    std::vector<Work> work;
    for (uint32_t t = 0; t < triangles.size(); ++t) {
        const auto& tri = triangles[t];
        const Vec3f e1 = (x[tri[1]] - x[tri[0]]).head<3>(), e2 = (x[tri[2]] - x[tri[0]]).head<3>();
        const float sigma = inverse_rest_[t].isZero() ? reference_[t] : mesh::largest_stretch(inverse_rest_[t], e1, e2);
        stretch_[t] = sigma;
        const float ratio = sigma / reference_[t];
        const int8_t side = ratio > options_.grow ? 1 : ratio < options_.shrink && sigma > 0.0f ? -1 : 0;
        int8_t& run = beyond_[t];
        // Frames in a row on this side, counted up to 120 (the settle limit is at most 60).
        run = side == 0 ? 0 : run * side > 0 ? int8_t(side * std::min(std::abs(int(run)) + 1, 120)) : side;
        if (uint32_t(std::abs(run)) < std::max(1u, options_.settle_frames)) continue;
        work.push_back({std::abs(std::log(ratio)), t, side > 0});
    }
    if (!work.empty() && options_.enabled) {
        const size_t take = std::min<size_t>(work.size(), options_.budget);
        std::partial_sort(work.begin(), work.begin() + take, work.end(),
                          [](const Work& a, const Work& b) { return a.priority > b.priority; });
        stats.pending = uint32_t(work.size() - take);
        work.resize(take);
        stats.resampled = uint32_t(take);
        PBDSPLAT_ASSERT(s.position.size() == s.size(), "density control: update the boundary particles' positions first");
        const Rows by_triangle = make_rows(triangles.size(), s.size(), [&](size_t i) { return s.triangle[i]; });
        const Rows ring = make_rows(x.size(), triangles.size() * 3, [&](size_t i) { return triangles[i / 3][i % 3]; });
        // The triangles sharing a vertex with t (t included), each once per call.
        std::vector<uint32_t> mark(triangles.size(), 0);
        uint32_t stamp = 0;
        auto around = [&](uint32_t t, auto&& visit) {
            ++stamp;
            for (uint32_t v : triangles[t])
                for (uint32_t c : ring[v]) {
                    const uint32_t n = c / 3;
                    if (mark[n] == stamp) continue;
                    mark[n] = stamp;
                    visit(n);
                }
        };
        s.pad_fades();
        const float step = 1.0f / float(std::max(1u, options_.fade_frames));
        const bool embedded = s.embedded();
        thread_local std::vector<uint32_t> same;
        thread_local PointGrid grid(h, 256);  // reset per triangle: no allocation once warm
        for (const Work& w : work) {
            const uint32_t t = w.triangle;
            const auto& tri = triangles[t];
            const Vec3f a = x[tri[0]].head<3>(), b = x[tri[1]].head<3>(), c = x[tri[2]].head<3>();
            same.assign(by_triangle[t].begin(), by_triangle[t].end());
            if (w.grow) {
                grid.reset(options_.insert_spacing * h);
                around(t, [&](uint32_t n) {
                    for (uint32_t i : by_triangle[n])
                        if (!s.retiring(i)) grid.add(s.position[i]);
                    if (anchors_drawn)
                        for (uint32_t v : triangles[n]) grid.add(x[v].head<3>());
                });
                // Samples this frame already added to the neighbours (not in by_triangle yet).
                for (size_t i = by_triangle.items.size(); i < s.size(); ++i) grid.add(s.position[i]);
                const Mat3f frame = triangle_frame(a, b, c);
                const float area = 0.5f * (b - a).cross(c - a).norm();
                const float expected = area * options_.candidates / (h * h);
                std::mt19937 rng(seed ^ uint32_t(frame_ * 0x9E3779B1u) ^ (t * 0x85EBCA6Bu));
                std::uniform_real_distribution<float> u(0.0f, 1.0f);
                uint32_t n = uint32_t(expected);
                if (u(rng) < expected - float(n)) ++n;
                for (uint32_t k = 0; k < n; ++k) {
                    float b1 = u(rng), b2 = u(rng);
                    if (b1 + b2 > 1.0f) b1 = 1.0f - b1, b2 = 1.0f - b2;
                    const float b0 = 1.0f - b1 - b2;
                    const Vec3f interpolated = b0 * normals[tri[0]] + b1 * normals[tri[1]] + b2 * normals[tri[2]];
                    float d = 0.0f;
                    Vec3f local = Vec3f::UnitZ();
                    if (embedded) interpolate_embedding(s, same, Vec2f(b1, b2), d, local);
                    const Vec3f p = b0 * a + b1 * b + b2 * c + d * interpolated;
                    if (grid.near(p)) continue;
                    if (max_samples_ && s.size() >= max_samples_) {
                        stats.capped = true;
                        break;
                    }
                    grid.add(p);
                    s.triangle.push_back(t);
                    s.bary.emplace_back(b1, b2);
                    if (embedded) s.offset.push_back(d), s.local_normal.push_back(local);
                    s.position.push_back(p);
                    const float len = interpolated.norm();
                    s.normal.push_back(embedded ? Vec3f(frame * local) : len > 0.0f ? Vec3f(interpolated / len) : frame.col(2));
                    s.fade.push_back(0.0f);
                    s.fade_step.push_back(step);
                    ++stats.inserted;
                }
            } else {
                grid.reset(options_.retire_spacing * h);
                around(t, [&](uint32_t n) {
                    if (n != t)
                        for (uint32_t i : by_triangle[n])
                            if (!s.retiring(i)) grid.add(s.position[i]);
                    if (anchors_drawn)
                        for (uint32_t v : triangles[n]) grid.add(x[v].head<3>());
                });
                for (uint32_t i : same) {
                    if (s.retiring(i) || s.on_edge(i)) continue;  // edge samples follow the boundary (surface/edges.h)
                    if (grid.near(s.position[i])) {
                        s.fade_step[i] = -step;
                        ++stats.retired;
                    } else {
                        grid.add(s.position[i]);
                    }
                }
            }
            reference_[t] = stretch_[t];
            beyond_[t] = 0;
        }
    }
    stats.removed = uint32_t(advance_fades(s, &stats.fading));
    return stats;
}

size_t advance_fades(BoundaryParticles& s, uint32_t* fading) {
    uint32_t still = 0;
    bool remove = false;
    const size_t n = std::min(s.fade.size(), s.fade_step.size());
    for (size_t i = 0; i < n; ++i) {
        if (s.fade_step[i] == 0.0f) continue;
        s.fade[i] = std::clamp(s.fade[i] + s.fade_step[i], 0.0f, 1.0f);
        if (s.fade_step[i] > 0.0f && s.fade[i] >= 1.0f) s.fade_step[i] = 0.0f;
        else if (s.fade_step[i] < 0.0f && s.fade[i] <= 0.0f) remove = true;
        else ++still;
    }
    if (fading) *fading = still;
    if (!remove) return 0;
    return s.keep_if([&](size_t i) { return !(s.retiring(i) && s.fade[i] <= 0.0f); });
}

void fade_in(BoundaryParticles& s, size_t first, uint32_t frames) {
    s.pad_fades();
    const float step = 1.0f / float(std::max(1u, frames));
    for (size_t i = first; i < s.size(); ++i) {
        s.fade[i] = 0.0f;
        s.fade_step[i] = step;
    }
}

SpacingReport spacing_report(std::span<const Vec3f> points, float h, float low, float high) {
    SpacingReport r;
    r.points = points.size();
    if (points.size() < 2) return r;
    // Cells of 2h: a nearest neighbour farther than that counts as "too far" anyway.
    PointGrid grid(2.0f * h, points.size());
    for (const Vec3f& p : points) grid.add(p);
    std::vector<float> d(points.size());
    size_t in = 0;
    for (size_t i = 0; i < points.size(); ++i) {
        const float d2 = grid.nearest_squared(points[i], uint32_t(i));
        d[i] = std::isfinite(d2) ? std::sqrt(d2) / h : 2.0f;
        in += d[i] >= low && d[i] <= high;
    }
    r.within = float(in) / float(points.size());
    auto q = [&](float f) {
        const size_t k = std::min(d.size() - 1, size_t(f * float(d.size())));
        std::nth_element(d.begin(), d.begin() + k, d.end());
        return d[k];
    };
    r.p05 = q(0.05f);
    r.median = q(0.5f);
    r.p95 = q(0.95f);
    return r;
}

} // namespace pbdsplat::surface
