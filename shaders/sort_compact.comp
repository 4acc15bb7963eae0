#version 460
// Depth sort, step 3: the visible splats' keys and record indices, packed in their original
// order (counts[] holds each tile's first output slot, from the scan), so the sort that follows
// is stable with respect to the records' order, as std::stable_sort on the CPU is.
#include "sort_visibility.glsl"

void main() {
    const uint first = gl_WorkGroupID.x * SORT_TILE + gl_LocalInvocationID.x * SORT_ITEMS;
    uint mine = 0u;
    for (uint j = 0u; j < SORT_ITEMS; ++j) {
        uint key;
        if (first + j < pc.count && sort_visible(first + j, key)) ++mine;
    }
    uint out_index = counts[gl_WorkGroupID.x] + workgroup_exclusive_scan(mine);
    for (uint j = 0u; j < SORT_ITEMS; ++j) {
        uint key;
        if (first + j < pc.count && sort_visible(first + j, key)) {
            keys[out_index] = key;
            values[out_index] = first + j;
            ++out_index;
        }
    }
}
