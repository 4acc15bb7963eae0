#version 460
// Depth sort, last step: the records in far-to-near order for the draw, and the indirect draw
// arguments of every splat path. The tail up to a whole mesh-shader workgroup is filled with
// zero-scale records, which every path draws as nothing.
#include "sort_common.glsl"

layout(set = 0, binding = 2, std430) readonly buffer Records { uint record_words[]; };
layout(set = 0, binding = 5, std430) writeonly buffer Sorted { uint sorted_words[]; };

void main() {
    const uint i = gl_GlobalInvocationID.x;
    const uint n = control[SORT_CONTROL_VISIBLE];
    const uint groups = (n + SORT_MESH_GROUP - 1u) / SORT_MESH_GROUP;
    if (i == 0u) {
        control[SORT_CONTROL_DRAW + 0] = n;
        control[SORT_CONTROL_DRAW + 1] = 1u;
        control[SORT_CONTROL_DRAW + 2] = 0u;
        control[SORT_CONTROL_DRAW + 3] = 0u;
        control[SORT_CONTROL_DRAW_PULL + 0] = 6u * n;
        control[SORT_CONTROL_DRAW_PULL + 1] = 1u;
        control[SORT_CONTROL_DRAW_PULL + 2] = 0u;
        control[SORT_CONTROL_DRAW_PULL + 3] = 0u;
        control[SORT_CONTROL_MESH + 0] = groups;
        control[SORT_CONTROL_MESH + 1] = 1u;
        control[SORT_CONTROL_MESH + 2] = 1u;
    }
    if (i >= groups * SORT_MESH_GROUP) return;
    const uint words = SPLAT_RECORD_SIZE / 4;
    if (i < n) {
        const uint src = values[i] * words;
        for (uint w = 0u; w < words; ++w) sorted_words[i * words + w] = record_words[src + w];
    } else {
        for (uint w = 0u; w < words; ++w) sorted_words[i * words + w] = 0u;
    }
}
