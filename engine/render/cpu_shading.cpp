#include "render/cpu_shading.h"

#include <algorithm>
#include <cmath>

namespace pbdsplat::render {

namespace {
Vec3f direct_light(const Vec3f& albedo, const Vec3f& n, const Vec3f& t, const Vec3f& l, const Vec3f& radiance,
                   float specular, float shininess) {
    const float nl = std::max(n.dot(l), 0.0f);
    if (nl <= 0.0f) return Vec3f::Zero();
    const float spec = std::pow(std::max(n.dot((l + t).normalized()), 0.0f), shininess);
    return (albedo * nl + Vec3f::Constant(specular * spec)).cwiseProduct(radiance);
}
} // namespace

Vec3f shade_cpu(const CpuShading& s, const Vec3f& albedo, const Vec3f& normal, const Vec3f& world, uint32_t model) {
    const Lighting& l = *s.lighting;
    const Vec3f t = (s.eye - world).normalized();  // towards the eye
    // A normal facing away is lit as the splat pass lights it (shading.glsl, splat_lit_normal):
    // turned round for opaque discs, laid onto the view plane for soft Gaussians.
    Vec3f n = normal;
    if (const float d = normal.dot(t); d < 0.0f) n = s.opaque_discs ? Vec3f(-normal) : Vec3f((normal - d * t + 1e-4f * t).normalized());
    Vec3f color = direct_light(albedo, n, t, l.direction.normalized(), l.color * l.intensity, l.specular, l.shininess);
    const Environment& e = l.environment;
    if (e.sampling == EnvSampling::off) {
        color += albedo.cwiseProduct(l.ambient);
    } else {
        // Eq. 24: p is the world position seen from the body's centre (its model's).
        const Vec3f rel = world - (model < e.model_centers.size() ? e.model_centers[model] : e.center);
        const Vec3f p = rel.squaredNorm() > 1e-12f ? Vec3f(rel.normalized()) : n;
        const Vec3f diffuse_dir = e.sampling == EnvSampling::position ? p : n;
        const Vec3f specular_dir = e.sampling == EnvSampling::normal ? n : p;
        const float g = (l.shininess + 2.0f) / (l.shininess + 8.0f);
        const Vec3f e_d = albedo.cwiseProduct(evaluate_sh(s.sh, diffuse_dir)) / float(k_pi) * e.diffuse;
        Vec3f e_s = Vec3f::Zero();
        if (s.map) {
            const Vec3f r = -t - 2.0f * (-t).dot(specular_dir) * specular_dir;  // reflect(-t, specular_dir)
            e_s = sample_nearest(*s.map, r) * l.specular * e.specular * g;
        }
        color += (e_d + e_s) * e.intensity;
    }
    // Eq. 25: point, spot and directional lights.
    for (size_t k = 0; k < std::min(l.lights.size(), k_max_lights); ++k) {
        const Light& li = l.lights[k];
        Vec3f dir = li.direction.normalized();
        float attenuation = 1.0f;
        if (li.type != LightType::directional) {
            const Vec3f to_light = li.position - world;
            const float d = to_light.norm();
            dir = to_light / std::max(d, 1e-6f);
            const float fall = std::clamp(1.0f - d / li.range, 0.0f, 1.0f);
            attenuation = fall * fall;
            if (li.type == LightType::spot)
                attenuation *= math::smoothstep(std::cos(math::radians(li.outer_degrees)), std::cos(math::radians(li.inner_degrees)),
                                          (-dir).dot(li.direction.normalized()));
        }
        color += direct_light(albedo, n, t, dir, li.color * li.intensity * attenuation, l.specular, l.shininess);
    }
    return color;
}

} // namespace pbdsplat::render
