// The optional stream of anisotropic splats' axes (binding 3; layout in gpu_types.h). Every
// splat pipeline declares it; only those specialised with k_anisotropic read it.
#ifndef PBDSPLAT_SPLAT_SHAPE_GLSL
#define PBDSPLAT_SPLAT_SHAPE_GLSL

layout(constant_id = 5) const bool k_anisotropic = false;
layout(set = 0, binding = 3, std430) readonly buffer Shapes { uint shape_words[]; };
#include "splat_stream_order.glsl"

// Columns: the Gaussian's three axes in world units (covariance = A A^T); `i`: the splat's
// place in the draw.
mat3 read_shape_axes(uint i) {
    const uint base = stream_entry(i) * (SPLAT_SHAPE_SIZE / 4);
    const vec2 h0 = unpackHalf2x16(shape_words[base + 0]);
    const vec2 h1 = unpackHalf2x16(shape_words[base + 1]);
    const vec2 h2 = unpackHalf2x16(shape_words[base + 2]);
    const vec2 h3 = unpackHalf2x16(shape_words[base + 3]);
    const vec2 h4 = unpackHalf2x16(shape_words[base + 4]);
    return mat3(vec3(h0.x, h0.y, h1.x), vec3(h1.y, h2.x, h2.y), vec3(h3.x, h3.y, h4.x));
}

#endif
