#version 460
// Mesh raster pass (coverage reference): the deformed simulation mesh, positions as float4.
#include "gpu_types.h"

layout(set = 0, binding = 0, std140) uniform Frame { FrameUniforms frame; };
layout(location = 0) in vec4 in_position;

void main() { gl_Position = frame.proj * frame.view * vec4(in_position.xyz, 1.0); }
