#version 460
// Splat pass, visibility stage of the Gaussian footprint: only the opaque core of each splat
// writes depth (pushed back by the front stage), giving the colour stage a surface to test
// against without sorting.
#include "gpu_types.h"

layout(set = 0, binding = 0, std140) uniform Frame { FrameUniforms frame; };

layout(location = 0) in vec2 g_uv;     // standard deviations
layout(location = 3) in vec4 g_color;  // a: opacity times the fade

void main() {
    const vec2 u = g_uv / frame.splat.yz;
    // The same falloff as the colour stage: only fragments opaque enough to stand for the
    // surface write depth.
    if (g_color.a * exp(-0.5 * dot(u, u)) < frame.visibility.z) discard;
}
