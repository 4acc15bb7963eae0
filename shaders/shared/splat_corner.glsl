// What every splat path hands the fragment stage for one carrier corner. With per-corner
// shading (specialization constant 1) the lighting of eqs. 24-25 is evaluated here, at the
// corner's world position, and interpolated: a few evaluations per splat instead of one per
// covered pixel, which on a fill-bound device is most of the pass. Per-fragment shading (the
// paper's) passes the albedo on and shades in splat.frag.
// Needs `frame`, `env_map` and shading.glsl before inclusion.
#ifndef PBDSPLAT_SPLAT_CORNER_GLSL
#define PBDSPLAT_SPLAT_CORNER_GLSL

layout(constant_id = 1) const bool k_shade_per_corner = false;

#include "splat_sh.glsl"

// The splat's colour before lighting: the record's (degree 0), plus the view-dependent degrees of
// a trained file, seen from the eye towards the splat's centre.
vec3 splat_albedo(vec3 rgb, uint index, vec3 world) {
    if (k_sh_degree == 0u) return rgb;
    return max(rgb + sh_rest_color(index, normalize(world - frame.camera_pos.xyz)), vec3(0.0));
}

// The splat's opacity: sigmoid(o) (eq. 21) times the fade-in.
float splat_alpha(float fade, float opacity_logit) { return sigmoid(opacity_logit) * fade; }

// rgb: the albedo, or the shaded colour; a: the splat's opacity (splat_alpha).
vec4 corner_color(vec3 albedo, float alpha, vec3 normal, vec3 corner_world) {
    const vec3 rgb = k_shade_per_corner
                         ? shade(albedo, splat_lit_normal(normal, corner_world, k_footprint == SPLAT_FOOTPRINT_PAPER), corner_world)
                         : albedo;
    return vec4(rgb, alpha);
}

#endif
