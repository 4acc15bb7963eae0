#version 460
// Splat pass, fragment stage: elliptical Gaussian mask (paper section 5.6.1) and shading
// (section 5.6.2), with premultiplied alpha for the "over" blend.
#include "gpu_types.h"

layout(set = 0, binding = 0, std140) uniform Frame { FrameUniforms frame; };
layout(set = 0, binding = 1) uniform sampler2D env_map;
#include "shading.glsl"

layout(constant_id = 1) const bool k_shade_per_corner = false;

layout(location = 0) in vec2 g_uv;
layout(location = 1) in vec3 g_world;
layout(location = 2) in vec3 g_normal;
layout(location = 3) in vec4 g_color;  // rgb: albedo, or the colour shaded at the corners; a: opacity

layout(location = 0) out vec4 out_color;

// The colour pass tests depth without writing it, so testing before the shader runs changes
// nothing but the cost: fragments hidden behind the visibility pass's surface are never shaded
// (a discard cannot turn off early tests here, because nothing is written).
layout(early_fragment_tests) in;

void main() {
    // Eqs. 22-23: normalise by the sharpness and discard outside the unit ellipse.
    const vec2 u = g_uv / frame.splat.yz;
    const float r2 = dot(u, u);
    if (r2 > 1.0) discard;
    // The quad spans kappa standard deviations, so r = 1 sits at kappa sigma.
    const float kappa = frame.splat.x;
    const float weight = exp(-0.5 * kappa * kappa * r2);
    const float alpha = clamp(g_color.a * weight, 0.0, 1.0);  // eq. 21 times the fade
    const vec3 color = k_shade_per_corner ? g_color.rgb : shade(g_color.rgb, normalize(g_normal), g_world);
    out_color = vec4(color * alpha, alpha);
}
