// Which records a depth sort keeps, and their keys: splats whose cut-off sphere (kappa standard
// deviations) lies outside the view frustum, or whose scale is zero or not a number, are culled.
#ifndef PBDSPLAT_SORT_VISIBILITY_GLSL
#define PBDSPLAT_SORT_VISIBILITY_GLSL

#include "sort_common.glsl"
#include "splat_record.glsl"

bool sort_visible(uint i, out uint key) {
    const uint base = i * (SPLAT_RECORD_SIZE / 4);
    const vec3 p = vec3(uintBitsToFloat(record_words[base + 0]), uintBitsToFloat(record_words[base + 1]),
                        uintBitsToFloat(record_words[base + 2]));
    const float scale = unpackHalf2x16(record_words[base + SPLAT_OFFSET_SCALE_OPACITY / 4]).x;
    const float r = pc.limits.z * scale;
    const float z = dot(pc.depth_row, vec4(p, 1.0));
    key = sortable_key(z);
    if (!(r > 0.0) || isinf(r) || any(isnan(p))) return false;
    if (-z < pc.limits.x - r || -z > pc.limits.y + r) return false;
    for (int k = 0; k < 4; ++k)
        if (dot(pc.planes[k].xyz, p) + pc.planes[k].w < -r) return false;
    return true;
}

#endif
