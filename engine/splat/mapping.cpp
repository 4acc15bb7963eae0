#include "splat/mapping.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/assert.h"
#include "mesh/deformation.h"
#include "surface/thin_order.h"

namespace pbdsplat::splat {

static_assert(surface::k_thin_levels == SPLAT_THIN_LEVELS, "the thinning order's levels are the shaders'");

namespace {
// A sample's rank within its thinning level: a hash of where it lies on its triangle, so the
// same sample keeps it from frame to frame (and a sample a change moved takes another).
int thin_rank_of(uint32_t triangle, const Vec2f& bary) {
    uint32_t bx, by;
    std::memcpy(&bx, &bary.x(), 4);
    std::memcpy(&by, &bary.y(), 4);
    uint32_t h = triangle * 0x9E3779B1u ^ bx * 0x85EBCA77u ^ by * 0xC2B2AE3Du;
    h ^= h >> 15;
    h *= 0x2C1B3C6Du;
    h ^= h >> 12;
    return int(h >> 26);
}
// Twice the area over the longest edge squared: 0.87 for an equilateral triangle; below this a
// triangle counts as a sliver.
constexpr float k_min_shape_quality = 0.02f;
constexpr float k_max_stretch_factor = 3.0f;
} // namespace

StretchScale::StretchScale(std::span<const Vec3f> rest, std::span<const mesh::Triangle> triangles) {
    // A sliver (a cut's re-triangulation makes some) keeps factor 1: its neighbours cover it.
    inverse_rest_.resize(triangles.size());
    for (size_t t = 0; t < triangles.size(); ++t)
        inverse_rest_[t] = mesh::rest_frame_inverse(rest[triangles[t][0]], rest[triangles[t][1]], rest[triangles[t][2]],
                                                    k_min_shape_quality);
    const size_t n = rest.size();
    ring_start_.assign(n + 1, 0);
    for (const auto& t : triangles)
        for (uint32_t v : t) ++ring_start_[v + 1];
    for (size_t i = 0; i < n; ++i) ring_start_[i + 1] += ring_start_[i];
    ring_.resize(ring_start_.back());
    std::vector<uint32_t> fill(ring_start_.begin(), ring_start_.end() - 1);
    for (uint32_t t = 0; t < triangles.size(); ++t)
        for (uint32_t v : triangles[t]) ring_[fill[v]++] = t;
    triangle_.assign(triangles.size(), 1.0f);
    vertex_.assign(n, 1.0f);
}

void StretchScale::update(std::span<const Vec4f> x, std::span<const mesh::Triangle> triangles) {
    for (size_t t = 0; t < triangles.size(); ++t) {
        const Vec3f e1 = (x[triangles[t][1]] - x[triangles[t][0]]).head<3>();
        const Vec3f e2 = (x[triangles[t][2]] - x[triangles[t][0]]).head<3>();
        // Zero inverse (a sliver): factor 1. Otherwise at most k_max_stretch_factor, so no
        // splat ever grows past a few spacings whatever the mesh does.
        triangle_[t] = std::clamp(mesh::largest_stretch(inverse_rest_[t], e1, e2), 1.0f, k_max_stretch_factor);
    }
    for (size_t v = 0; v + 1 < ring_start_.size(); ++v) {
        float m = 1.0f;
        for (uint32_t r = ring_start_[v]; r < ring_start_[v + 1]; ++r) m = std::max(m, triangle_[ring_[r]]);
        vertex_[v] = m;
    }
}

// Below this many samples handing ranges to threads costs more than it saves.
constexpr size_t k_parallel_samples = 8192;

void map_body(std::span<const Vec4f> x, std::span<const Vec3f> normals, std::span<const Vec3f> colors,
              std::span<const mesh::Triangle> triangles, const surface::BoundaryParticles* samples, const Appearance& look,
              const StretchScale* stretch, const NormalField* field, std::vector<GaussianRecord>& out,
              core::ThreadPool* pool, std::span<const uint8_t> kept) {
    const size_t n = x.size(), m = samples ? samples->size() : 0;
    PBDSPLAT_ASSERT(kept.empty() || (kept.size() == m && out.size() >= n + m), "map_body: kept records must be there");
    out.resize(n + m);
    map_points(x, normals, look, std::span<GaussianRecord>(out.data(), n));
    const GaussianRecord base = make_record(Vec3f::Zero(), Vec3f::UnitZ(), look);
    auto color_bytes = [](const Vec3f& c, GaussianRecord& r) {
        for (int k = 0; k < 3; ++k) r.color[k] = to_unorm8(c[k]);
    };
    if (!colors.empty())
        for (size_t i = 0; i < n; ++i) color_bytes(colors[i], out[i]);
    const bool stretched = stretch && !stretch->empty();
    if (stretched)
        for (size_t i = 0; i < n; ++i) out[i].scale_half = float_to_half(look.scale * stretch->vertex(uint32_t(i)));
    if (field && field->has_vertices())
        for (size_t i = 0; i < n; ++i) set_curvature(field->vertex(uint32_t(i)), normals[i], out[i]);
    // What each sample has is known per body, not per sample.
    const size_t with_color = std::min(m, samples ? samples->color.size() : 0);
    const size_t with_fade = std::min(m, samples ? samples->fade.size() : 0);
    const size_t with_level = std::min(m, samples ? samples->thin_level.size() : 0);
    // Each sample's record is its own: the threads take ranges of them.
    const auto map_samples = [&](size_t first, size_t last) {
    for (size_t k = first; k < last; ++k) {
        if (!kept.empty() && kept[k]) continue;
        GaussianRecord r = base;
        const Vec3f& p = samples->position[k];
        r.position[0] = p.x(), r.position[1] = p.y(), r.position[2] = p.z();
        encode_octahedral(samples->normal[k], r.normal_oct);
        const uint32_t t = samples->triangle[k];
        if (k < with_color && (samples->color[k] >> 24) != 0) {
            const uint32_t c = samples->color[k];
            r.color[0] = uint8_t(c), r.color[1] = uint8_t(c >> 8), r.color[2] = uint8_t(c >> 16);
        } else if (!colors.empty()) {
            const auto& tri = triangles[t];
            const Vec2f b = samples->bary[k];
            color_bytes((1.0f - b.x() - b.y()) * colors[tri[0]] + b.x() * colors[tri[1]] + b.y() * colors[tri[2]], r);
        }
        const float grown = std::max(samples->growth_of(t), stretched ? stretch->triangle(t) : 1.0f);
        const float size = samples->size_of(k) * grown;
        if (size != 1.0f) r.scale_half = float_to_half(look.scale * size);
        // The curvature's left-out axis and the thinning place share entry 3: written once.
        const int axis = field ? set_curvature_entries(field->triangle(t), samples->normal[k], r) : 0;
        if (k < with_fade) r.color[3] = to_unorm8(samples->fade[k]);
        if (k < with_level) r.curvature_half[3] = pack_curvature_w(axis, samples->thin_level[k], thin_rank_of(t, samples->bary[k]));
        else if (field) r.curvature_half[3] = pack_curvature_w(axis, SPLAT_THIN_LEVELS, 0);
        out[n + k] = r;
    }
    };
    if (pool && pool->size() > 1 && m >= k_parallel_samples) pool->parallel_for(m, [&](unsigned, size_t b, size_t e) { map_samples(b, e); });
    else map_samples(0, m);
}

} // namespace pbdsplat::splat
