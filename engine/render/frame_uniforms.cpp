#include "render/frame_uniforms.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace pbdsplat::render {
namespace {
gpu_types::mat4 to_gpu(const Mat4f& m) {
    gpu_types::mat4 out;
    std::memcpy(out.m, m.data(), sizeof(out.m));  // Eigen is column-major, like GLSL
    return out;
}
gpu_types::vec4 to_gpu(const Vec3f& v, float w) { return {v.x(), v.y(), v.z(), w}; }
} // namespace

float paper_kappa(const SplatStyle& s) { return s.kappa > 0.0f ? s.kappa : k_paper_closing_kappa; }

float splat_reach_bound(const SplatStyle& s) {
    float sigmas = 0.0f;
    if (s.footprint == Footprint::paper) {
        sigmas = paper_kappa(s);
    } else {
        sigmas = std::sqrt(2.0f * std::log(255.0f)) * std::max(s.sharpness.x(), s.sharpness.y());
        if (s.kappa > 0.0f) sigmas = std::min(sigmas, s.kappa);
    }
    return sigmas * s.scale_multiplier;
}

gpu_types::FrameUniforms make_frame_uniforms(const FrameInputs& in, uint32_t width, uint32_t height, const std::array<Vec3f, 9>* sh) {
    const Camera& c = in.camera;
    gpu_types::FrameUniforms u{};
    u.view = to_gpu(math::look_at(c.eye, c.target, c.up));
    u.proj = to_gpu(math::perspective(math::radians(c.fov_y_degrees), float(width) / float(height), c.z_near, c.z_far));
    u.camera_pos = to_gpu(c.eye, 1.0f);
    u.viewport = {float(width), float(height), 1.0f / float(width), 1.0f / float(height)};
    const Lighting& l = in.lighting;
    u.light_dir = to_gpu(l.direction.normalized(), l.intensity);
    u.light_color = to_gpu(l.color, 0.0f);
    u.ambient = to_gpu(l.ambient, l.specular);
    const SplatStyle& s = in.style;
    const float kappa = s.footprint == Footprint::paper ? paper_kappa(s) : s.kappa;
    u.splat = {kappa, s.sharpness.x(), s.sharpness.y(), s.scale_multiplier};
    u.material = {l.shininess, s.surfel_thickness, s.blend == Blend::normalised ? s.thin_below : 0.0f, 0.0f};
    u.interior = {s.interior.x(), s.interior.y(), s.interior.z(), s.interior.w()};
    u.visibility = {s.depth_push, s.cull_facing, s.depth_min_alpha, s.mesh_occluders ? s.occluder_tolerance : 0.0f};
    const Environment& e = l.environment;
    u.environment = {float(int(e.sampling)), e.diffuse, e.specular, e.intensity};
    const size_t lights = std::min<size_t>(l.lights.size(), PBDSPLAT_MAX_LIGHTS);
    u.env_center = to_gpu(e.center, float(lights));
    for (size_t k = 0; k < 9; ++k) u.env_sh[k] = to_gpu(sh ? (*sh)[k] : Vec3f::Zero(), 0.0f);
    for (size_t k = 0; k < SPLAT_ENV_CENTERS; ++k) u.env_centers[k] = to_gpu(k < e.model_centers.size() ? e.model_centers[k] : e.center, 0.0f);
    for (size_t k = 0; k < lights; ++k) {
        const Light& g = l.lights[k];
        const bool directional = g.type == LightType::directional;
        u.light_position[k] = to_gpu(directional ? Vec3f(g.direction.normalized()) : g.position, float(int(g.type)));
        u.light_radiance[k] = to_gpu(g.color * g.intensity, g.range);
        u.light_spot[k] = to_gpu(g.direction.normalized(), 0.0f);
        u.light_cone[k] = {std::cos(math::radians(g.inner_degrees)), std::cos(math::radians(g.outer_degrees)), 0.0f, 0.0f};
    }
    return u;
}

} // namespace pbdsplat::render
