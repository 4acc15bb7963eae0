#version 460
// Depth sort, radix pass part 1: how many keys of each tile have each value of the current
// 4-bit digit, stored digit-major (counts[digit * tiles + tile]) so that one exclusive scan
// gives every tile its first output slot per digit.
#include "sort_common.glsl"

shared uint s_hist[SORT_BINS];

void main() {
    const uint t = gl_LocalInvocationID.x;
    if (t < SORT_BINS) s_hist[t] = 0u;
    barrier();
    const uint n = control[SORT_CONTROL_VISIBLE];
    const uint first = gl_WorkGroupID.x * SORT_TILE + t * SORT_ITEMS;
    for (uint j = 0u; j < SORT_ITEMS; ++j)
        if (first + j < n) atomicAdd(s_hist[(keys[pc.src_offset + first + j] >> pc.shift) & (SORT_BINS - 1u)], 1u);
    barrier();
    if (t < SORT_BINS) counts[t * pc.tiles + gl_WorkGroupID.x] = s_hist[t];
}
