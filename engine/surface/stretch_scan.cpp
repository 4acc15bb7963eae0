#include "surface/stretch_scan.h"

#include <bit>
#include <cstring>

#if defined(__SSE2__)
#include <emmintrin.h>
#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
#include <immintrin.h>
#define PBDSPLAT_EIGHT_LANES 1
#endif
#endif

namespace pbdsplat::surface {
// Named, not only anonymous: a unity build puts other files' helpers in the same unit.
namespace stretch_scan_lanes {

#if defined(__SSE2__)
// Bit k set where beyond[k] != 0, for `count` (4 or 8) bytes.
uint32_t counting(const int8_t* beyond, size_t count) {
    alignas(16) uint8_t bytes[16] = {};
    std::memcpy(bytes, beyond, count);
    const __m128i zero = _mm_cmpeq_epi8(_mm_load_si128(reinterpret_cast<const __m128i*>(bytes)), _mm_setzero_si128());
    return ~uint32_t(_mm_movemask_epi8(zero)) & ((1u << count) - 1u);
}

void append(std::vector<uint32_t>& busy, size_t t, uint32_t lanes) {
    for (; lanes != 0; lanes &= lanes - 1) busy.push_back(uint32_t(t) + uint32_t(std::countr_zero(lanes)));
}

// The lane operations the scan uses, each with its four- and eight-lane form: one list, made
// into each width's helpers by PICK (the first form, or the second).
#define PBDSPLAT_PICK_FOUR(four, eight) four
#define PBDSPLAT_PICK_EIGHT(four, eight) eight
#define PBDSPLAT_LANE_OPERATIONS(PICK)                                                                   \
    inline V add(V x, V y) { return PICK(_mm_add_ps, _mm256_add_ps)(x, y); }                             \
    inline V sub(V x, V y) { return PICK(_mm_sub_ps, _mm256_sub_ps)(x, y); }                             \
    inline V mul(V x, V y) { return PICK(_mm_mul_ps, _mm256_mul_ps)(x, y); }                             \
    inline V maximum(V x, V y) { return PICK(_mm_max_ps, _mm256_max_ps)(x, y); }                         \
    inline V either(V x, V y) { return PICK(_mm_or_ps, _mm256_or_ps)(x, y); }                            \
    inline V less(V x, V y) { return PICK(_mm_cmplt_ps(x, y), _mm256_cmp_ps(x, y, _CMP_LT_OS)); }        \
    inline V greater(V x, V y) { return PICK(_mm_cmpgt_ps(x, y), _mm256_cmp_ps(x, y, _CMP_GT_OS)); }     \
    inline V unordered(V x, V y) { return PICK(_mm_cmpunord_ps(x, y), _mm256_cmp_ps(x, y, _CMP_UNORD_Q)); } \
    inline V square_root(V x) { return PICK(_mm_sqrt_ps, _mm256_sqrt_ps)(x); }                           \
    inline V set1(float f) { return PICK(_mm_set1_ps, _mm256_set1_ps)(f); }                              \
    inline V load(const float* p) { return PICK(_mm_loadu_ps, _mm256_loadu_ps)(p); }                     \
    inline void store(float* p, V x) { PICK(_mm_storeu_ps, _mm256_storeu_ps)(p, x); }                   \
    inline uint32_t lane_mask(V x) { return uint32_t(PICK(_mm_movemask_ps, _mm256_movemask_ps)(x)); }

namespace four {
using V = __m128;
constexpr size_t k_lanes = 4;
PBDSPLAT_LANE_OPERATIONS(PBDSPLAT_PICK_FOUR)

// Four triangles' edges, one per lane: the corners transposed as they load.
inline void load_edges(const StretchScan& s, size_t t, V* e1, V* e2) {
    for (size_t k = 0; k < 4; ++k) {
        const mesh::Triangle& tri = s.triangles[t + k];
        const V o = load(s.x[tri[0]].data());
        e1[k] = sub(load(s.x[tri[1]].data()), o);
        e2[k] = sub(load(s.x[tri[2]].data()), o);
    }
    _MM_TRANSPOSE4_PS(e1[0], e1[1], e1[2], e1[3]);
    _MM_TRANSPOSE4_PS(e2[0], e2[1], e2[2], e2[3]);
}
// The block's inverse rest frames (t a multiple of 4).
inline void load_rest(const float* rest, V& a, V& c, V& b, V& d) {
    a = load(rest), c = load(rest + 4), b = load(rest + 8), d = load(rest + 12);
}

#include "surface/stretch_scan_kernel.h"
} // namespace four
#endif

#if defined(PBDSPLAT_EIGHT_LANES)
// The eight-lane scan is compiled for AVX alone (everything up to pop_options).
#pragma GCC push_options
#pragma GCC target("avx")
namespace eight {
using V = __m256;
constexpr size_t k_lanes = 8;
PBDSPLAT_LANE_OPERATIONS(PBDSPLAT_PICK_EIGHT)

inline V pair(const float* low, const float* high) {
    return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(low)), _mm_loadu_ps(high), 1);
}
// Two blocks of four at a time: row k holds triangle t + k in its low half and t + 4 + k in its
// high half; after the transpose (x, y, z into rows 0-2) triangle t + j is in lane j.
inline void transpose(V* r) {
    const V t0 = _mm256_unpacklo_ps(r[0], r[1]), t1 = _mm256_unpackhi_ps(r[0], r[1]);
    const V t2 = _mm256_unpacklo_ps(r[2], r[3]), t3 = _mm256_unpackhi_ps(r[2], r[3]);
    r[0] = _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(1, 0, 1, 0));
    r[1] = _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(3, 2, 3, 2));
    r[2] = _mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(1, 0, 1, 0));
}
inline void load_edges(const StretchScan& s, size_t t, V* e1, V* e2) {
    for (size_t k = 0; k < 4; ++k) {
        const mesh::Triangle& lo = s.triangles[t + k];
        const mesh::Triangle& hi = s.triangles[t + 4 + k];
        const V o = pair(s.x[lo[0]].data(), s.x[hi[0]].data());
        e1[k] = sub(pair(s.x[lo[1]].data(), s.x[hi[1]].data()), o);
        e2[k] = sub(pair(s.x[lo[2]].data(), s.x[hi[2]].data()), o);
    }
    transpose(e1);
    transpose(e2);
}
// Two blocks' inverse rest frames, block by block in the two halves.
inline void load_rest(const float* rest, V& a, V& c, V& b, V& d) {
    a = pair(rest, rest + 16), c = pair(rest + 4, rest + 20), b = pair(rest + 8, rest + 24), d = pair(rest + 12, rest + 28);
}

#include "surface/stretch_scan_kernel.h"
} // namespace eight
#pragma GCC pop_options
#endif
#undef PBDSPLAT_LANE_OPERATIONS
#undef PBDSPLAT_PICK_FOUR
#undef PBDSPLAT_PICK_EIGHT

} // namespace stretch_scan_lanes

bool eight_lanes_available() {
#if defined(PBDSPLAT_EIGHT_LANES)
    // libgcc's answer includes the operating system's support (XGETBV) for the wide registers.
    static const bool avx = __builtin_cpu_supports("avx");
    return avx;
#else
    return false;
#endif
}

size_t scan_stretches(const StretchScan& s, std::vector<uint32_t>& busy, ScanLanes lanes) {
#if defined(__SSE2__)
    size_t t = 0;
#if defined(PBDSPLAT_EIGHT_LANES)
    if (lanes != ScanLanes::four && eight_lanes_available()) t = stretch_scan_lanes::eight::scan(s, 0, busy);
#else
    (void)lanes;
#endif
    return stretch_scan_lanes::four::scan(s, t, busy);
#else
    (void)s, (void)busy, (void)lanes;
    return 0;
#endif
}

} // namespace pbdsplat::surface
