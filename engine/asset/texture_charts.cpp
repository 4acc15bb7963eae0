#include "asset/texture_charts.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace pbdsplat::asset {

namespace {

// Texture coordinates that read the same texel: equal, or apart by whole repeats where the
// texture wraps so.
bool same_place(const Vec2f& a, const Vec2f& b, const Texture* t) {
    constexpr float tol = 1e-4f;
    for (int k = 0; k < 2; ++k) {
        float d = std::abs(a[k] - b[k]);
        const Wrap w = t ? (k == 0 ? t->wrap_u : t->wrap_v) : Wrap::clamp;
        if (w == Wrap::repeat) d = std::abs(d - std::round(d));
        if (d > tol) return false;
    }
    return true;
}

uint64_t position_key(const Vec3f& p) {
    uint32_t b[3];
    std::memcpy(b, p.data(), sizeof(b));
    uint64_t h = 1469598103934665603ull;
    for (uint32_t v : b) h = (h ^ v) * 1099511628211ull;
    return h;
}

} // namespace

uint64_t TextureCharts::key(int x, int y, int z) const {
    return (uint64_t(uint32_t(x) & 0x1FFFFF) << 42) | (uint64_t(uint32_t(y) & 0x1FFFFF) << 21) | uint64_t(uint32_t(z) & 0x1FFFFF);
}

namespace {

// An edge welded by position (files split a seam's vertices to give each side its own
// coordinates): its corners' keys in order, and what the first triangle met on it reads there.
struct EdgeRead {
    int32_t texture;
    Vec2f uv_low, uv_high;  // at the lower key's corner, the higher's
    bool seam = false;
};

struct PairHash {
    size_t operator()(const std::pair<uint64_t, uint64_t>& k) const { return size_t(k.first * 0x9E3779B97F4A7C15ull ^ k.second); }
};

} // namespace

TextureCharts::TextureCharts(const SurfaceLook& look) {
    if (look.uv.size() != look.triangles.size() || look.triangles.empty()) return;
    // A seam is an edge whose two sides read different places of the texture (or different
    // textures) at its corners. A corner alone is not enough: a quad's diagonal joins two
    // corners that lie on seams, and runs through the middle of its chart.
    std::unordered_map<std::pair<uint64_t, uint64_t>, EdgeRead, PairHash> edges;
    double length = 0.0;
    for (size_t t = 0; t < look.triangles.size(); ++t) {
        const uint32_t material = t < look.material.size() ? look.material[t] : 0u;
        const int32_t texture = material < look.materials.size() ? look.materials[material].texture : -1;
        const Texture* tex = texture >= 0 && size_t(texture) < look.textures.size() ? &look.textures[size_t(texture)] : nullptr;
        for (int k = 0; k < 3; ++k) {
            const Vec3f &p = look.positions[look.triangles[t][size_t(k)]], &q = look.positions[look.triangles[t][size_t((k + 1) % 3)]];
            length += (q - p).norm();
            uint64_t a = position_key(p), b = position_key(q);
            Vec2f ua = look.uv[t][size_t(k)], ub = look.uv[t][size_t((k + 1) % 3)];
            if (b < a) std::swap(a, b), std::swap(ua, ub);
            const auto [it, fresh] = edges.try_emplace({a, b}, EdgeRead{texture, ua, ub});
            if (!fresh && (it->second.texture != texture || !same_place(it->second.uv_low, ua, tex) || !same_place(it->second.uv_high, ub, tex)))
                it->second.seam = true;
        }
    }
    const float mean_edge = std::max(float(length / double(3 * look.triangles.size())), 1e-6f);
    cell_ = 2.0f * mean_edge;
    spacing_ = 0.1f * mean_edge;
    // Each seam edge as points a tenth of a mean edge apart, its corners included, so a long
    // seam edge is seen from its middle too.
    std::unordered_map<uint64_t, bool> corners;
    for (size_t t = 0; t < look.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) {
            const Vec3f &p = look.positions[look.triangles[t][size_t(k)]], &q = look.positions[look.triangles[t][size_t((k + 1) % 3)]];
            const uint64_t a = position_key(p), b = position_key(q);
            EdgeRead& e = edges.at({std::min(a, b), std::max(a, b)});
            if (!e.seam) continue;
            e.seam = false;  // once per edge
            const int steps = std::max(1, int(std::ceil((q - p).norm() / spacing_)));
            for (int i = 1; i < steps; ++i) insert(p + (q - p) * (float(i) / float(steps)));
            for (const auto& [key, at] : {std::pair(a, p), std::pair(b, q)})
                if (corners.try_emplace(key, true).second) insert(at), ++seam_count_;
        }
}

void TextureCharts::insert(const Vec3f& p) {
    cells_[key(int(std::floor(p.x() / cell_)), int(std::floor(p.y() / cell_)), int(std::floor(p.z() / cell_)))].push_back(p);
}

float TextureCharts::seam_distance(const Vec3f& p, float reach) const {
    if (cells_.empty() || !(reach > 0.0f)) return reach;
    const int r = int(std::ceil(reach / cell_));
    const int cx = int(std::floor(p.x() / cell_)), cy = int(std::floor(p.y() / cell_)), cz = int(std::floor(p.z() / cell_));
    float best2 = reach * reach;
    for (int x = cx - r; x <= cx + r; ++x)
        for (int y = cy - r; y <= cy + r; ++y)
            for (int z = cz - r; z <= cz + r; ++z) {
                const auto it = cells_.find(key(x, y, z));
                if (it == cells_.end()) continue;
                for (const Vec3f& q : it->second) best2 = std::min(best2, (q - p).squaredNorm());
            }
    // Between two of the seam's points it runs up to half their spacing nearer.
    return best2 < reach * reach ? std::max(0.0f, std::sqrt(best2) - 0.5f * spacing_) : reach;
}

std::optional<UvGradient> uv_gradient(const SurfaceLook& look, uint32_t t) {
    if (t >= look.uv.size() || t >= look.triangles.size()) return std::nullopt;
    const mesh::Triangle& tri = look.triangles[t];
    const Vec3f e1 = look.positions[tri[1]] - look.positions[tri[0]], e2 = look.positions[tri[2]] - look.positions[tri[0]];
    const Vec2f a = look.uv[t][1] - look.uv[t][0], b = look.uv[t][2] - look.uv[t][0];
    const float g11 = e1.dot(e1), g12 = e1.dot(e2), g22 = e2.dot(e2), det = g11 * g22 - g12 * g12;
    if (!(det > 1e-12f * g11 * g22)) return std::nullopt;
    // grad = c1 e1 + c2 e2 with grad . e1 = a and grad . e2 = b: the Gram matrix solves for c.
    const auto along = [&](float da, float db) {
        const float c1 = (g22 * da - g12 * db) / det, c2 = (g11 * db - g12 * da) / det;
        return Vec3f(c1 * e1 + c2 * e2);
    };
    const float uv_area = std::abs(a.x() * b.y() - a.y() * b.x());
    if (!(uv_area > 0.0f)) return std::nullopt;
    UvGradient g{along(a.x(), b.x()), along(a.y(), b.y())};
    if (!g.du.allFinite() || !g.dv.allFinite()) return std::nullopt;
    return g;
}

} // namespace pbdsplat::asset
