#version 460
// The scene's ground plane: a disc on the plane collider around the body, drawn before the
// splats so a body resting on it reads as resting (and its far side below it stays hidden).
#include "gpu_types.h"

layout(set = 0, binding = 0, std140) uniform Frame { FrameUniforms frame; };
layout(push_constant) uniform Push { GroundPush ground; };

layout(location = 0) out vec3 v_world;

const vec2 k_corners[6] = vec2[6](vec2(-1, -1), vec2(1, -1), vec2(-1, 1), vec2(-1, 1), vec2(1, -1), vec2(1, 1));

void main() {
    const vec3 n = ground.plane.xyz;
    // Any two tangents spanning the plane.
    const vec3 t = normalize(abs(n.y) < 0.9 ? cross(n, vec3(0, 1, 0)) : cross(n, vec3(1, 0, 0)));
    const vec3 b = cross(n, t);
    const vec2 c = k_corners[gl_VertexIndex] * ground.disc.w;
    // Drawn a thousandth of its radius below the plane: a sheet or a flat face lying on the
    // plane (where the collider holds its particles) would otherwise share its depth, and the
    // ground's shadow show through it in streaks wherever the two depths round the other way.
    v_world = ground.disc.xyz + c.x * t + c.y * b - n * (1e-3 * ground.disc.w);
    gl_Position = frame.proj * frame.view * vec4(v_world, 1.0);
}
