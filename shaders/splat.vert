#version 460
// Splat pass, vertex stage: unpacks one Gaussian record and hands it to the geometry shader.
#include "gpu_types.h"
#include "splat_codec.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec2 in_normal_oct;
layout(location = 2) in vec4 in_color;
layout(location = 3) in vec2 in_scale_opacity;
layout(location = 4) in vec4 in_curvature;

layout(location = 0) out vec3 v_normal;
layout(location = 1) out vec4 v_color;
layout(location = 2) out vec2 v_scale_opacity;
layout(location = 3) out mat3 v_curvature;  // locations 3-5
layout(location = 6) out vec2 v_thin;  // splat_thin_place()
layout(location = 7) flat out uint v_model;

void main() {
    gl_Position = vec4(in_position, 1.0);  // world position; the geometry shader projects
    v_normal = decode_octahedral(in_normal_oct);
    v_color = in_color;
    v_scale_opacity = in_scale_opacity;
    v_curvature = splat_curvature(in_curvature, v_normal);
    v_thin = splat_thin_place(in_curvature);
    v_model = splat_model_of(in_normal_oct);
}
