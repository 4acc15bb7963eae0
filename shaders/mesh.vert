#version 460
// Mesh raster pass: the deformed simulation mesh (positions as float4, w the vertex's model;
// normals per vertex), the mesh-based pipeline the paper compares against and the reference for
// coverage metrics.
#include "gpu_types.h"

layout(set = 0, binding = 0, std140) uniform Frame { FrameUniforms frame; };
layout(location = 0) in vec4 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec3 in_color;  // the model's own colour (ones for a plain material)
layout(location = 3) in vec2 in_uv;     // read only where the draw samples a texture

layout(location = 0) out vec3 v_world;
layout(location = 1) out vec3 v_normal;
layout(location = 2) out vec3 v_color;
layout(location = 3) out vec2 v_uv;
layout(location = 4) flat out uint v_model;  // the vertex's model (w), whose centre lights it

void main() {
    v_world = in_position.xyz;
    v_normal = in_normal;
    v_color = in_color;
    v_uv = in_uv;
    v_model = uint(max(in_position.w, 0.0) + 0.5);
    gl_Position = frame.proj * frame.view * vec4(in_position.xyz, 1.0);
}
