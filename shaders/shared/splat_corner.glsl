// What every splat path hands the fragment stage for one carrier corner. With per-corner
// shading (specialization constant 1) the lighting of eqs. 24-25 is evaluated here, at the
// corner's world position, and interpolated: a few evaluations per splat instead of one per
// covered pixel, which on a fill-bound device is most of the pass. Per-fragment shading (the
// paper's) passes the albedo on and shades in splat.frag.
// Needs `frame`, `env_map` and shading.glsl before inclusion.
#ifndef PBDSPLAT_SPLAT_CORNER_GLSL
#define PBDSPLAT_SPLAT_CORNER_GLSL

layout(constant_id = 1) const bool k_shade_per_corner = false;
layout(constant_id = 7) const bool k_opaque_surface = false;  // as in splat_fragment.glsl

#include "splat_sh.glsl"

// The splat's colour before lighting: the record's (degree 0), plus the view-dependent degrees of
// a trained file, seen from the eye towards the splat's centre.
vec3 splat_albedo(vec3 rgb, uint index, vec3 world) {
    if (k_sh_degree == 0u) return rgb;
    return max(rgb + sh_rest_color(index, normalize(world - frame.camera_pos.xyz)), vec3(0.0));
}

// The splat's opacity: sigmoid(o) (eq. 21) times the fade-in.
float splat_alpha(float fade, float opacity_logit) { return sigmoid(opacity_logit) * fade; }

// The normal at a carrier corner (unnormalised; the fragment stage normalises the interpolated
// one). The record's curvature S says how the surface's normal turns per unit of distance in the
// splat's tangent plane; the corner stands for the point where the view ray through it meets
// that plane. The field is linear in the carrier's position, so interpolating the corners' is
// exact, and it never passes through zero between them (below: each keeps a part towards the
// side the splat faces).
vec3 corner_normal(vec3 n, mat3 curvature, vec3 centre_world, vec3 corner_world) {
    if (curvature[0] == vec3(0.0) && curvature[1] == vec3(0.0) && curvature[2] == vec3(0.0)) return n;
    const vec3 d = corner_world - centre_world;  // in the view plane
    const vec3 v = normalize(frame.camera_pos.xyz - centre_world);
    const float nv = dot(n, v);
    // Seen at a grazing angle the plane meets the ray far out: at most about three times the
    // carrier's reach (the splat is a sliver there anyway).
    const float nv_safe = nv >= 0.0 ? max(nv, 0.3) : min(nv, -0.3);
    const vec3 p = d - v * (dot(n, d) / nv_safe);
    vec3 m = n + curvature * p;
    // Where a disc reaches past the silhouette the turn carries its normal over the horizon,
    // and the fragment stage would light it as the far side (a dark rim): stop it at grazing,
    // on the side the splat's own normal faces.
    const float side = nv >= 0.0 ? 1.0 : -1.0;
    const float lift = 0.05 * length(m) - side * dot(m, v);
    if (lift > 0.0) m += side * lift * v;
    return m;
}

// rgb: the albedo, or the shaded colour; a: the splat's opacity (splat_alpha).
vec4 corner_color(vec3 albedo, float alpha, vec3 normal, vec3 corner_world, uint model) {
    const vec3 rgb = k_shade_per_corner
                         ? shade(albedo, splat_lit_normal(normalize(normal), corner_world, k_footprint == SPLAT_FOOTPRINT_PAPER, k_opaque_surface),
                                 corner_world, model)
                         : albedo;
    return vec4(rgb, alpha);
}

#endif
