#pragma once
// Environment maps (paper section 5.6.2): an equirectangular radiance image, from a file (PNG,
// sRGB-decoded, or Radiance HDR) or made procedurally, and its diffuse irradiance as nine
// spherical-harmonic coefficients, so the shader's diffuse term costs no texture fetch.
#include <array>
#include <string>
#include <vector>

#include "core/math.h"
#include "core/result.h"

namespace pbdsplat::render {

struct EnvironmentMap {
    uint32_t width = 0, height = 0;  // longitude across, latitude down (v = 0: +y, the zenith)
    std::vector<float> rgba;         // linear radiance, 4 floats per texel
    Vec3f texel(uint32_t x, uint32_t y) const {
        const float* p = &rgba[(size_t(y) * width + x) * 4];
        return {p[0], p[1], p[2]};
    }
};

// The direction of texel centre (x, y), and the texel a direction falls in.
Vec3f equirect_direction(const EnvironmentMap& map, float x, float y);
Vec3f sample_nearest(const EnvironmentMap& map, const Vec3f& direction);

// A soft sky: a horizon-to-zenith gradient, a darker ground and a warm glow around `sun`.
EnvironmentMap procedural_sky(const Vec3f& sun, uint32_t width = 256, uint32_t height = 128);

// A photo studio: a dark room lit by two large soft boxes (key and fill, from `key`'s side and
// opposite) and a bright strip overhead; the "other environment map" of the paper's Figure 10.
EnvironmentMap procedural_studio(const Vec3f& key, uint32_t width = 256, uint32_t height = 128);

// The procedural maps by name, as scene files give them ("procedural:sky", "procedural:studio").
inline constexpr const char* k_procedural_prefix = "procedural:";
bool is_procedural_map_name(const std::string& name);

// PNG (8-bit, sRGB) or .hdr (Radiance RGBE) files; errors name the file and the reason.
core::Result<EnvironmentMap> load_environment_map(const std::string& path);

// `map_path` empty or "procedural:sky": the procedural sky lit from `sun`; "procedural:studio":
// the studio; anything else: a PNG or .hdr file.
core::Result<EnvironmentMap> make_environment_map(const std::string& map_path, const Vec3f& sun);

// Irradiance E(n) = sum_lm A_l L_lm Y_lm(n) (Ramamoorthi and Hanrahan 2001): coefficients with
// the cosine lobe A_l already applied, in the order Y00, Y1-1, Y10, Y11, Y2-2, Y2-1, Y20, Y21, Y22.
std::array<Vec3f, 9> irradiance_sh(const EnvironmentMap& map);
Vec3f evaluate_sh(const std::array<Vec3f, 9>& sh, const Vec3f& n);

} // namespace pbdsplat::render
