#version 460
// Splat pass, visibility stage: only the opaque core of each splat writes depth (pushed back by
// the geometry stage), giving the colour stage a surface to test against without sorting.
#include "gpu_types.h"

layout(set = 0, binding = 0, std140) uniform Frame { FrameUniforms frame; };

layout(location = 0) in vec2 g_uv;

void main() {
    const vec2 u = g_uv / frame.splat.yz;
    if (dot(u, u) > frame.visibility.y) discard;
}
