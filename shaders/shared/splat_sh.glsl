// The optional stream of view-dependent colour (binding 4; layout in gpu_types.h): degrees 1-3
// of a trained file's spherical harmonics, evaluated once per splat for the direction from the
// eye to its centre, as 3D Gaussian splatting defines them. Every splat pipeline declares it;
// only those specialised with k_sh_degree > 0 read it.
#ifndef PBDSPLAT_SPLAT_SH_GLSL
#define PBDSPLAT_SPLAT_SH_GLSL

layout(constant_id = 6) const uint k_sh_degree = 0u;
layout(set = 0, binding = 4, std430) readonly buffer ShRest { uint sh_words[]; };
#include "splat_stream_order.glsl"

float sh_coefficient(uint base, uint j) {
    const vec2 h = unpackHalf2x16(sh_words[base + j / 2u]);
    return (j & 1u) == 0u ? h.x : h.y;
}

// What degrees 1..k_sh_degree add to the splat's colour, seen along unit direction d; `index`:
// the splat's place in the draw.
vec3 sh_rest_color(uint index, vec3 d) {
    if (k_sh_degree == 0u) return vec3(0.0);
    const float x = d.x, y = d.y, z = d.z;
    const float xx = x * x, yy = y * y, zz = z * z;
    float b[15];
    const float c1 = 0.4886025119;
    b[0] = -c1 * y;
    b[1] = c1 * z;
    b[2] = -c1 * x;
    b[3] = 1.0925484306 * x * y;
    b[4] = -1.0925484306 * y * z;
    b[5] = 0.3153915653 * (2.0 * zz - xx - yy);
    b[6] = -1.0925484306 * x * z;
    b[7] = 0.5462742153 * (xx - yy);
    b[8] = -0.5900435899 * y * (3.0 * xx - yy);
    b[9] = 2.8906114426 * x * y * z;
    b[10] = -0.4570457995 * y * (4.0 * zz - xx - yy);
    b[11] = 0.3731763326 * z * (2.0 * zz - 3.0 * xx - 3.0 * yy);
    b[12] = -0.4570457995 * x * (4.0 * zz - xx - yy);
    b[13] = 1.4453057213 * z * (xx - yy);
    b[14] = -0.5900435899 * x * (xx - 3.0 * yy);
    const uint n = k_sh_degree == 1u ? 3u : k_sh_degree == 2u ? 8u : 15u;
    const uint base = stream_entry(index) * (SPLAT_SH_SIZE / 4u);
    vec3 c = vec3(0.0);
    for (uint k = 0u; k < n; ++k)
        c += b[k] * vec3(sh_coefficient(base, k), sh_coefficient(base, 15u + k), sh_coefficient(base, 30u + k));
    return c;
}

#endif
