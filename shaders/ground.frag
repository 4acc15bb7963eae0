#version 460
// The ground disc: lit by the key light and the ambient term, darkened under the body by a soft
// contact shadow, fading out towards its rim so it has no edge to see.
#include "gpu_types.h"

layout(set = 0, binding = 0, std140) uniform Frame { FrameUniforms frame; };
layout(push_constant) uniform Push { GroundPush ground; };

layout(location = 0) in vec3 v_world;
layout(location = 0) out vec4 out_color;

void main() {
    const float r = length(v_world - ground.disc.xyz) / ground.disc.w;
    if (r > 1.0) discard;
    const vec3 n = ground.plane.xyz;
    const float lambert = max(dot(n, frame.light_dir.xyz), 0.0) * frame.light_dir.w;
    // The contact shadows: each strongest under its piece's centre, fading out past its outline;
    // where two overlap the darker one holds.
    float shadow = 0.0;
    for (int k = 0; k < GROUND_SHADOWS; ++k) {
        const float d = length(v_world - ground.shadow[k].xyz);
        shadow = max(shadow, ground.strength[k] * (1.0 - smoothstep(0.3 * ground.shadow[k].w, 1.6 * ground.shadow[k].w, d)));
    }
    const vec3 light = frame.ambient.rgb + (1.0 - shadow) * lambert * frame.light_color.rgb;
    const vec3 color = ground.albedo.rgb * light * (1.0 - 0.5 * shadow);
    const float alpha = 1.0 - smoothstep(0.6, 1.0, r);
    out_color = vec4(color * alpha, alpha);
}
