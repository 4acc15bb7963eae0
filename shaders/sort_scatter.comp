#version 460
// Depth sort, radix pass part 2: every key (and its record index) moves to its slot for the
// current digit. Within a tile the order is kept by ranking each invocation's keys after those
// of earlier invocations with the same digit: the pass is stable, so eight of them sort by the
// whole key and keep equal keys in their input order.
#include "sort_common.glsl"

shared uint s_rank[SORT_BINS * SORT_THREADS];  // digit-major: [digit][invocation]

void main() {
    const uint t = gl_LocalInvocationID.x;
    const uint n = control[SORT_CONTROL_VISIBLE];
    const uint first = gl_WorkGroupID.x * SORT_TILE + t * SORT_ITEMS;
    uint mine[SORT_BINS];
    for (uint d = 0u; d < SORT_BINS; ++d) mine[d] = 0u;
    for (uint j = 0u; j < SORT_ITEMS; ++j)
        if (first + j < n) ++mine[(keys[pc.src_offset + first + j] >> pc.shift) & (SORT_BINS - 1u)];
    for (uint d = 0u; d < SORT_BINS; ++d) s_rank[d * SORT_THREADS + t] = mine[d];
    barrier();
    // Exclusive scan of the digit-major array: each invocation owns SORT_BINS consecutive entries.
    uint sum = 0u;
    for (uint e = 0u; e < SORT_BINS; ++e) sum += s_rank[t * SORT_BINS + e];
    uint running = workgroup_exclusive_scan(sum);
    for (uint e = 0u; e < SORT_BINS; ++e) {
        const uint c = s_rank[t * SORT_BINS + e];
        s_rank[t * SORT_BINS + e] = running;
        running += c;
    }
    barrier();
    // Slot = the tile's first slot for the digit + keys of that digit before this invocation's.
    uint next[SORT_BINS];
    for (uint d = 0u; d < SORT_BINS; ++d)
        next[d] = counts[d * pc.tiles + gl_WorkGroupID.x] + s_rank[d * SORT_THREADS + t] - s_rank[d * SORT_THREADS];
    for (uint j = 0u; j < SORT_ITEMS; ++j) {
        if (first + j >= n) break;
        const uint key = keys[pc.src_offset + first + j];
        const uint d = (key >> pc.shift) & (SORT_BINS - 1u);
        const uint slot = next[d]++;
        keys[pc.dst_offset + slot] = key;
        values[pc.dst_offset + slot] = values[pc.src_offset + first + j];
    }
}
