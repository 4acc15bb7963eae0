#version 460
// Depth sort, step 1: how many splats of each tile survive culling (counts[tile]).
#include "sort_visibility.glsl"

void main() {
    const uint first = gl_WorkGroupID.x * SORT_TILE + gl_LocalInvocationID.x * SORT_ITEMS;
    uint mine = 0u;
    for (uint j = 0u; j < SORT_ITEMS; ++j) {
        uint key;
        if (first + j < pc.count && sort_visible(first + j, key)) ++mine;
    }
    const uint before = workgroup_exclusive_scan(mine);
    if (gl_LocalInvocationID.x == SORT_THREADS - 1) counts[gl_WorkGroupID.x] = before + mine;
}
