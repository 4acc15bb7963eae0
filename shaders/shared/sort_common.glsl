// Shared by the depth-sort kernels (render/gpu_sort.h). Every kernel works on tiles of
// SORT_TILE elements, each invocation on SORT_ITEMS consecutive ones, and exchanges counts only
// through shared memory and barriers: nothing assumes a subgroup size (Lavapipe's is 8, many
// GPUs' 32 or 64).
#ifndef PBDSPLAT_SORT_COMMON_GLSL
#define PBDSPLAT_SORT_COMMON_GLSL

#include "gpu_types.h"

#define SORT_THREADS 128
#define SORT_ITEMS 8
#define SORT_TILE (SORT_THREADS * SORT_ITEMS)
#define SORT_BINS 16  // 4-bit digits: eight passes over 32-bit keys

layout(local_size_x = SORT_THREADS) in;
layout(push_constant, std430) uniform Push { SortPush pc; };

layout(set = 0, binding = 0, std430) buffer Keys { uint keys[]; };        // two halves of `capacity`
layout(set = 0, binding = 1, std430) buffer Values { uint values[]; };    // record indices, same halves
layout(set = 0, binding = 3, std430) buffer Counts { uint counts[]; };    // per tile (and digit)
layout(set = 0, binding = 4, std430) buffer Control { uint control[]; };  // SORT_CONTROL_*

shared uint s_partial[SORT_THREADS];

// Exclusive prefix of `mine` over the workgroup's invocations, in invocation order; returns it
// and leaves the workgroup's total in s_partial[SORT_THREADS - 1] + mine of the last.
uint workgroup_exclusive_scan(uint mine) {
    const uint t = gl_LocalInvocationID.x;
    s_partial[t] = mine;
    barrier();
    // Hillis-Steele in place: read, sync, write, sync.
    for (uint step = 1; step < SORT_THREADS; step <<= 1) {
        const uint add = t >= step ? s_partial[t - step] : 0u;
        barrier();
        s_partial[t] += add;
        barrier();
    }
    return s_partial[t] - mine;
}

// Monotonic map of a float to an unsigned key: ascending keys = ascending floats.
uint sortable_key(float f) {
    const uint u = floatBitsToUint(f);
    return (u & 0x80000000u) != 0u ? ~u : u | 0x80000000u;
}

#endif
