#version 460
// Depth sort: exclusive prefix sum of counts[0, scan_length) in place, by one workgroup (the
// arrays are a few thousand entries: tiles, or tiles times digits).
#include "sort_common.glsl"

void main() {
    const uint t = gl_LocalInvocationID.x;
    const uint chunk = (pc.scan_length + SORT_THREADS - 1u) / SORT_THREADS;
    const uint begin = min(t * chunk, pc.scan_length), end = min(begin + chunk, pc.scan_length);
    uint sum = 0u;
    for (uint i = begin; i < end; ++i) sum += counts[i];
    uint running = workgroup_exclusive_scan(sum);
    for (uint i = begin; i < end; ++i) {
        const uint c = counts[i];
        counts[i] = running;
        running += c;
    }
    if (t == SORT_THREADS - 1u && pc.write_total != 0u) control[SORT_CONTROL_VISIBLE] = running;
}
