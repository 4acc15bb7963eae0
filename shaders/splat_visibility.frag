#version 460
// Splat pass, visibility stage: only the opaque core of each splat writes depth (pushed back by
// the geometry stage), giving the colour stage a surface to test against without sorting.
#include "gpu_types.h"

layout(set = 0, binding = 0, std140) uniform Frame { FrameUniforms frame; };

layout(location = 0) in vec2 g_uv;
layout(location = 3) in vec4 g_color;  // a: opacity times the fade

void main() {
    const vec2 u = g_uv / frame.splat.yz;
    const float r2 = dot(u, u);
    if (r2 > frame.visibility.y) discard;
    // The same falloff as the colour stage (splat.frag): only fragments opaque enough to stand
    // for the surface write depth.
    const float kappa = frame.splat.x;
    if (g_color.a * exp(-0.5 * kappa * kappa * r2) < frame.visibility.z) discard;
}
