#version 460
// Mesh raster pass: a plain coverage mask, or the surface lit exactly as the splats are
// (shading.glsl), for side-by-side views and image comparisons.
#include "gpu_types.h"

layout(set = 0, binding = 0, std140) uniform Frame { FrameUniforms frame; };
layout(set = 0, binding = 1) uniform sampler2D env_map;
layout(set = 1, binding = 0) uniform sampler2D base_color;  // the model's texture (sRGB, read linear)
#include "shading.glsl"

layout(constant_id = 0) const bool k_mask = true;
layout(push_constant) uniform Push { vec4 albedo; } push;  // w: 1 where the draw is textured

layout(location = 0) in vec3 v_world;
layout(location = 1) in vec3 v_normal;
layout(location = 2) in vec3 v_color;
layout(location = 3) in vec2 v_uv;
layout(location = 4) flat in uint v_model;
layout(location = 0) out vec4 out_color;

void main() {
    // The mask's red channel says whether the outside of the surface is seen (1) or its inside,
    // through an opening (0): measures that compare shading look at the outside only.
    const bool outside = dot(v_normal, frame.camera_pos.xyz - v_world) >= 0.0;
    if (k_mask) {
        out_color = vec4(outside ? 1.0 : 0.0, 1.0, 1.0, 1.0);
        return;
    }
    // A cut opens the body: its inside faces the camera too, lit from the side that is seen.
    const vec3 n = seen_side(normalize(v_normal), v_world);
    const vec3 texel = push.albedo.w > 0.5 ? texture(base_color, v_uv).rgb : vec3(1.0);
    out_color = vec4(shade(push.albedo.rgb * v_color * texel, n, v_world, v_model), 1.0);
}
