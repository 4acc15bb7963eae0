#include "splat/texcoords.h"

#include <algorithm>
#include <cmath>

namespace pbdsplat::splat {

GaussianTexcoord make_texcoord(const Vec2f& uv, const Vec3f& du, const Vec3f& dv, uint32_t texture, const Vec3f& tint, float reach) {
    // Every sample, every frame: the in-range half conversion and a plain rounding, after clamps
    // that keep both in range (a gradient below half's smallest normal draws as flat).
    const auto half = [](float v) { return core::float_to_half_in_range(std::isfinite(v) ? std::clamp(v, -65504.0f, 65504.0f) : 0.0f); };
    GaussianTexcoord t;
    t.uv[0] = uv.x();
    t.uv[1] = uv.y();
    for (int k = 0; k < 3; ++k) {
        t.gradient_half[k] = half(du[k]);
        t.gradient_half[3 + k] = half(dv[k]);
        t.tint[k] = uint8_t(std::clamp(tint[k], 0.0f, 1.0f) * 255.0f + 0.5f);
    }
    t.texture = uint16_t(std::min<uint32_t>(texture, SPLAT_NO_TEXTURE));
    t.reach_half = half(std::max(reach, 0.0f));
    return t;
}

namespace {

// F^-T of triangle t for a covector at rest: [d1 d2 nd]^-T [e1 e2 ne]^T. Identity for a
// degenerate triangle (the splat keeps its rest gradients).
Mat3f covector_map(const Vec3f& a, const Vec3f& b, const Vec3f& c, const Vec3f& p, const Vec3f& q, const Vec3f& r) {
    Mat3f rest, now;
    const Vec3f e1 = b - a, e2 = c - a, d1 = q - p, d2 = r - p;
    const Vec3f ne = e1.cross(e2), nd = d1.cross(d2);
    if (!(ne.squaredNorm() > 0.0f) || !(nd.squaredNorm() > 0.0f)) return Mat3f::Identity();
    rest << e1, e2, ne.normalized();
    now << d1, d2, nd.normalized();
    bool invertible = false;
    Mat3f inverse;
    now.computeInverseWithCheck(inverse, invertible, 1e-20f);
    if (!invertible) return Mat3f::Identity();
    return inverse.transpose() * rest.transpose();
}

} // namespace

void map_texcoords(std::span<const Vec3f> rest_positions, std::span<const Vec4f> x, std::span<const mesh::Triangle> triangles,
                   size_t particles, std::span<const mesh::SurfaceTexcoord> particle_texcoords,
                   const surface::BoundaryParticles& samples, size_t records, std::vector<GaussianTexcoord>& out,
                   TexcoordScratch& scratch) {
    out.assign(records, GaussianTexcoord{});
    std::vector<Mat3f>& covector = scratch.covector;
    covector.resize(triangles.size());
    for (size_t t = 0; t < triangles.size(); ++t) {
        const mesh::Triangle& tri = triangles[t];
        covector[t] = covector_map(rest_positions[tri[0]], rest_positions[tri[1]], rest_positions[tri[2]], x[tri[0]].head<3>(),
                                   x[tri[1]].head<3>(), x[tri[2]].head<3>());
    }
    const auto put = [&](size_t record, const mesh::SurfaceTexcoord& c, const Mat3f& f) {
        if (c.texture >= 0) out[record] = make_texcoord(c.uv, f * c.du, f * c.dv, uint32_t(c.texture), c.tint, c.reach);
    };
    const size_t p = std::min({particles, particle_texcoords.size(), records});
    if (p > 0) {
        constexpr uint32_t none = ~0u;
        scratch.vertex_triangle.assign(p, none);
        for (size_t t = 0; t < triangles.size(); ++t)
            for (uint32_t v : triangles[t])
                if (v < p && scratch.vertex_triangle[v] == none) scratch.vertex_triangle[v] = uint32_t(t);
        for (size_t i = 0; i < p; ++i)
            if (scratch.vertex_triangle[i] != none) put(i, particle_texcoords[i], covector[scratch.vertex_triangle[i]]);
    }
    const size_t m = std::min({samples.texcoord.size(), samples.size(), records > particles ? records - particles : size_t(0)});
    for (size_t k = 0; k < m; ++k) put(particles + k, samples.texcoord[k], covector[samples.triangle[k]]);
}

} // namespace pbdsplat::splat
