#include "asset/look.h"

#include <algorithm>
#include <cmath>

namespace pbdsplat::asset {
namespace {

struct SrgbTable {
    float v[256];
    SrgbTable() {
        for (int i = 0; i < 256; ++i) {
            const float c = float(i) / 255.0f;
            v[i] = c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
        }
    }
};

int wrap_index(int i, int n, Wrap w) {
    switch (w) {
    case Wrap::clamp: return std::clamp(i, 0, n - 1);
    case Wrap::mirror: {
        const int period = 2 * n;
        int k = i % period;
        if (k < 0) k += period;
        return k < n ? k : period - 1 - k;
    }
    case Wrap::repeat:
    default: {
        const int k = i % n;
        return k < 0 ? k + n : k;
    }
    }
}

} // namespace

float srgb_to_linear(uint8_t v) {
    static const SrgbTable table;
    return table.v[v];
}

Vec3f srgb_to_linear(const Vec3f& c) {
    Vec3f out;
    for (int k = 0; k < 3; ++k) {
        const float v = std::clamp(c[k], 0.0f, 1.0f);
        out[k] = v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
    }
    return out;
}

Vec3f Texture::sample(const Vec2f& uv) const {
    if (width == 0 || height == 0 || rgba.size() < size_t(width) * height * 4) return Vec3f::Ones();
    // Texel centres sit at half-integers.
    const double x = double(uv.x()) * width - 0.5, y = double(uv.y()) * height - 0.5;
    if (!std::isfinite(x) || !std::isfinite(y)) return Vec3f::Ones();
    const double fx = std::floor(x), fy = std::floor(y);
    const float tx = float(x - fx), ty = float(y - fy);
    // Reduced to one mirror period (or held just outside the image when clamped) before the
    // conversion to int, so a coordinate far out (1e9) cannot overflow.
    const auto reduce = [](double f, uint32_t n, Wrap w) {
        return w == Wrap::clamp ? int(std::clamp(f, -1.0, double(n))) : int(std::fmod(f, 2.0 * n));
    };
    const int x0 = reduce(fx, width, wrap_u), y0 = reduce(fy, height, wrap_v);
    const int xs[2] = {wrap_index(x0, int(width), wrap_u), wrap_index(x0 + 1, int(width), wrap_u)};
    const int ys[2] = {wrap_index(y0, int(height), wrap_v), wrap_index(y0 + 1, int(height), wrap_v)};
    Vec3f out = Vec3f::Zero();
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
            const uint8_t* p = rgba.data() + (size_t(ys[j]) * width + size_t(xs[i])) * 4;
            const float w = (i ? tx : 1.0f - tx) * (j ? ty : 1.0f - ty);
            out += w * Vec3f(srgb_to_linear(p[0]), srgb_to_linear(p[1]), srgb_to_linear(p[2]));
        }
    return out;
}

bool SurfaceLook::has_colour() const {
    if (!corner_color.empty()) return true;
    for (const Material& m : materials)
        if (m.texture >= 0 || !m.color.isApprox(Vec3f::Ones())) return true;
    return false;
}

Vec3f SurfaceLook::color_at(uint32_t t, const Vec2f& b) const {
    const Parts p = parts_at(t, b);
    return p.texture >= 0 ? Vec3f(p.tint.cwiseProduct(textures[size_t(p.texture)].sample(p.uv))) : p.tint;
}

SurfaceLook::Parts SurfaceLook::parts_at(uint32_t t, const Vec2f& b) const {
    const float b0 = 1.0f - b.x() - b.y();
    Parts p;
    if (!material.empty() && material[t] < materials.size()) {
        const Material& m = materials[material[t]];
        p.tint = m.color;
        if (m.texture >= 0 && size_t(m.texture) < textures.size() && !uv.empty()) {
            const auto& q = uv[t];
            p.texture = m.texture;
            p.uv = b0 * q[0] + b.x() * q[1] + b.y() * q[2];
        }
    }
    if (!corner_color.empty()) {
        const auto& k = corner_color[t];
        p.tint = p.tint.cwiseProduct(b0 * k[0] + b.x() * k[1] + b.y() * k[2]);
    }
    return p;
}

} // namespace pbdsplat::asset
