#include "render/environment.h"

#include <algorithm>
#include <cmath>

#include <stb_image.h>

namespace pbdsplat::render {

namespace {
constexpr float k_pi = 3.14159265358979f;

float srgb_to_linear(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }

// The nine real SH basis functions at unit direction n.
std::array<float, 9> sh_basis(const Vec3f& n) {
    const float x = n.x(), y = n.y(), z = n.z();
    return {0.282095f,          0.488603f * y,         0.488603f * z,         0.488603f * x,
            1.092548f * x * y,  1.092548f * y * z,     0.315392f * (3.0f * z * z - 1.0f),
            1.092548f * x * z,  0.546274f * (x * x - y * y)};
}
} // namespace

Vec3f equirect_direction(const EnvironmentMap& m, float x, float y) {
    const float phi = (x / float(m.width) - 0.5f) * 2.0f * k_pi;  // longitude, atan2(z, x)
    const float theta = y / float(m.height) * k_pi;               // from +y
    return {std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)};
}

Vec3f sample_nearest(const EnvironmentMap& m, const Vec3f& d) {
    const Vec3f n = d.normalized();
    const float u = std::atan2(n.z(), n.x()) / (2.0f * k_pi) + 0.5f;
    const float v = std::acos(std::clamp(n.y(), -1.0f, 1.0f)) / k_pi;
    const uint32_t x = std::min(m.width - 1, uint32_t(std::max(0.0f, u * float(m.width))));
    const uint32_t y = std::min(m.height - 1, uint32_t(std::max(0.0f, v * float(m.height))));
    return m.texel(x, y);
}


EnvironmentMap procedural_studio(const Vec3f& key, uint32_t width, uint32_t height) {
    EnvironmentMap m;
    m.width = width;
    m.height = height;
    m.rgba.resize(size_t(width) * height * 4);
    const Vec3f k = Vec3f(key.x(), 0.3f, key.z()).normalized();
    const Vec3f fill = Vec3f(-k.x(), 0.1f, -k.z()).normalized();
    // A soft box: bright inside a cone, falling off smoothly at its rim.
    auto box = [](const Vec3f& d, const Vec3f& axis, float cos_inner, float cos_outer) {
        const float c = d.dot(axis);
        return std::clamp((c - cos_outer) / (cos_inner - cos_outer), 0.0f, 1.0f);
    };
    for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x) {
            const Vec3f d = equirect_direction(m, float(x) + 0.5f, float(y) + 0.5f);
            // Walls to floor, and the overhead strip, with soft edges (see the sky).
            Vec3f c = Vec3f(0.05f, 0.05f, 0.06f) + math::smoothstep(0.1f, -0.2f, d.y()) * Vec3f(0.04f, 0.03f, 0.01f);
            c += box(d, k, 0.93f, 0.88f) * Vec3f(3.0f, 2.9f, 2.7f);
            c += box(d, fill, 0.95f, 0.90f) * Vec3f(0.9f, 1.0f, 1.2f);
            c += math::smoothstep(0.8f, 0.9f, d.y()) * math::smoothstep(0.25f, 0.15f, std::abs(d.x())) * Vec3f(1.6f, 1.6f, 1.6f);
            float* p = &m.rgba[(size_t(y) * width + x) * 4];
            p[0] = c.x(), p[1] = c.y(), p[2] = c.z(), p[3] = 1.0f;
        }
    return m;
}

bool is_procedural_map_name(const std::string& name) {
    return name == std::string(k_procedural_prefix) + "sky" || name == std::string(k_procedural_prefix) + "studio";
}

EnvironmentMap procedural_sky(const Vec3f& sun, uint32_t width, uint32_t height) {
    EnvironmentMap m;
    m.width = width;
    m.height = height;
    m.rgba.resize(size_t(width) * height * 4);
    const Vec3f s = sun.normalized();
    const Vec3f zenith(0.22f, 0.36f, 0.70f), horizon(0.62f, 0.66f, 0.72f), ground(0.20f, 0.18f, 0.16f);
    for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x) {
            const Vec3f d = equirect_direction(m, float(x) + 0.5f, float(y) + 0.5f);
            // Smooth bands with no kink at the horizon: the position-based lookup maps the sky
            // onto a body by direction from its centre, and a kink draws a hard line across it.
            const float to_ground = math::smoothstep(0.05f, -0.45f, d.y()), to_zenith = math::smoothstep(-0.05f, 0.8f, d.y());
            Vec3f c = horizon + (ground - horizon) * to_ground + (zenith - horizon) * to_zenith;
            const float glow = std::pow(std::max(0.0f, d.dot(s)), 64.0f);
            c += glow * Vec3f(2.4f, 2.0f, 1.5f);
            float* p = &m.rgba[(size_t(y) * width + x) * 4];
            p[0] = c.x(), p[1] = c.y(), p[2] = c.z(), p[3] = 1.0f;
        }
    return m;
}

core::Result<EnvironmentMap> load_environment_map(const std::string& path) {
    int w = 0, h = 0, n = 0;
    EnvironmentMap m;
    const bool hdr = stbi_is_hdr(path.c_str()) != 0;
    if (hdr) {
        float* data = stbi_loadf(path.c_str(), &w, &h, &n, 4);
        if (!data) return core::make_error(path + ": cannot read the environment map (" + (stbi_failure_reason() ? stbi_failure_reason() : "unknown") + ")");
        m.rgba.assign(data, data + size_t(w) * size_t(h) * 4);
        stbi_image_free(data);
    } else {
        stbi_uc* data = stbi_load(path.c_str(), &w, &h, &n, 4);
        if (!data) return core::make_error(path + ": cannot read the environment map (" + (stbi_failure_reason() ? stbi_failure_reason() : "unknown") + ")");
        m.rgba.resize(size_t(w) * size_t(h) * 4);
        for (size_t i = 0; i < m.rgba.size(); ++i) m.rgba[i] = (i % 4 == 3) ? 1.0f : srgb_to_linear(float(data[i]) / 255.0f);
        stbi_image_free(data);
    }
    if (w < 4 || h < 2) return core::make_error(path + ": an environment map needs at least 4x2 texels");
    for (float v : m.rgba)
        if (!std::isfinite(v) || v < 0.0f) return core::make_error(path + ": the environment map holds negative or non-finite radiance");
    m.width = uint32_t(w);
    m.height = uint32_t(h);
    return m;
}

core::Result<EnvironmentMap> make_environment_map(const std::string& map_path, const Vec3f& sun) {
    if (map_path.empty() || map_path == std::string(k_procedural_prefix) + "sky") return procedural_sky(sun);
    if (map_path == std::string(k_procedural_prefix) + "studio") return procedural_studio(sun);
    return load_environment_map(map_path);
}

std::array<Vec3f, 9> irradiance_sh(const EnvironmentMap& m) {
    std::array<Vec3f, 9> L;
    L.fill(Vec3f::Zero());
    const float d_phi = 2.0f * k_pi / float(m.width), d_theta = k_pi / float(m.height);
    for (uint32_t y = 0; y < m.height; ++y) {
        const float theta = (float(y) + 0.5f) * d_theta;
        const float d_omega = std::sin(theta) * d_theta * d_phi;
        for (uint32_t x = 0; x < m.width; ++x) {
            const Vec3f c = m.texel(x, y) * d_omega;
            const auto basis = sh_basis(equirect_direction(m, float(x) + 0.5f, float(y) + 0.5f));
            for (int k = 0; k < 9; ++k) L[size_t(k)] += c * basis[size_t(k)];
        }
    }
    const float a[9] = {k_pi, 2.0f * k_pi / 3.0f, 2.0f * k_pi / 3.0f, 2.0f * k_pi / 3.0f, k_pi / 4.0f,
                        k_pi / 4.0f, k_pi / 4.0f, k_pi / 4.0f, k_pi / 4.0f};
    for (int k = 0; k < 9; ++k) L[size_t(k)] *= a[k];
    return L;
}

Vec3f evaluate_sh(const std::array<Vec3f, 9>& sh, const Vec3f& n) {
    const auto basis = sh_basis(n.normalized());
    Vec3f e = Vec3f::Zero();
    for (int k = 0; k < 9; ++k) e += sh[size_t(k)] * basis[size_t(k)];
    return e;
}

} // namespace pbdsplat::render
