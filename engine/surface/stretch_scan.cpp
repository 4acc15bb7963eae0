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

size_t scan_four(const StretchScan& s, size_t begin, std::vector<uint32_t>& busy) {
    // mesh::squared_stretches in four lanes, the corners transposed as they load, and the
    // thresholds tested in the same lanes: a lane where nothing changed by 5 %, nothing is past
    // a threshold and nothing was is quiet, and skips the per-triangle logic.
    const __m128 v_grow2 = _mm_set1_ps(s.grow2), v_shrink2 = _mm_set1_ps(s.shrink2);
    const __m128 v_squash2 = _mm_set1_ps(s.squash2), v_unsquash2 = _mm_set1_ps(s.unsquash2);
    const __m128 v_tiny = _mm_set1_ps(1e-12f), v_zero = _mm_setzero_ps(), v_half = _mm_set1_ps(0.5f), v_two = _mm_set1_ps(2.0f);
    const size_t n = s.triangles.size();
    size_t t = begin;
    for (; t + 4 <= n; t += 4) {
        __m128 e1[4], e2[4];
        for (size_t k = 0; k < 4; ++k) {
            const mesh::Triangle& tri = s.triangles[t + k];
            const __m128 o = _mm_loadu_ps(s.x[tri[0]].data());
            e1[k] = _mm_sub_ps(_mm_loadu_ps(s.x[tri[1]].data()), o);
            e2[k] = _mm_sub_ps(_mm_loadu_ps(s.x[tri[2]].data()), o);
        }
        _MM_TRANSPOSE4_PS(e1[0], e1[1], e1[2], e1[3]);
        _MM_TRANSPOSE4_PS(e2[0], e2[1], e2[2], e2[3]);
        const float* rest = s.rest_lanes + 4 * t;  // t is a multiple of 4: its block
        const __m128 a = _mm_loadu_ps(rest), c = _mm_loadu_ps(rest + 4), b = _mm_loadu_ps(rest + 8), d = _mm_loadu_ps(rest + 12);
        auto dot = [](const __m128* u, const __m128* v) {
            return _mm_add_ps(_mm_add_ps(_mm_mul_ps(u[0], v[0]), _mm_mul_ps(u[1], v[1])), _mm_mul_ps(u[2], v[2]));
        };
        const __m128 g11 = dot(e1, e1), g12 = dot(e1, e2), g22 = dot(e2, e2);
        auto form = [&](__m128 p, __m128 q) {  // (p, q) G (p, q)^T
            return _mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_mul_ps(p, p), g11), _mm_mul_ps(_mm_mul_ps(v_two, _mm_mul_ps(p, q)), g12)),
                              _mm_mul_ps(_mm_mul_ps(q, q), g22));
        };
        const __m128 p11 = form(a, c), p22 = form(b, d);
        const __m128 p12 = _mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_mul_ps(a, b), g11), _mm_mul_ps(_mm_add_ps(_mm_mul_ps(a, d), _mm_mul_ps(b, c)), g12)),
                                      _mm_mul_ps(_mm_mul_ps(c, d), g22));
        const __m128 half = _mm_mul_ps(v_half, _mm_add_ps(p11, p22)), diff = _mm_mul_ps(v_half, _mm_sub_ps(p11, p22));
        const __m128 root = _mm_sqrt_ps(_mm_add_ps(_mm_mul_ps(diff, diff), _mm_mul_ps(p12, p12)));
        const __m128 l2 = _mm_add_ps(half, root), s2 = _mm_max_ps(_mm_sub_ps(half, root), v_zero);
        _mm_storeu_ps(s.stretch2 + t, l2);
        _mm_storeu_ps(s.squeeze2 + t, s2);
        const __m128 ref2 = _mm_loadu_ps(s.reference2 + t);
        const __m128 ref_squeeze2 = _mm_max_ps(_mm_loadu_ps(s.reference_squeeze2 + t), v_tiny);
        __m128 any = _mm_or_ps(_mm_cmplt_ps(l2, _mm_loadu_ps(s.shrank_large2 + t)), _mm_cmplt_ps(s2, _mm_loadu_ps(s.shrank_small2 + t)));
        any = _mm_or_ps(any, _mm_or_ps(_mm_cmpgt_ps(l2, _mm_loadu_ps(s.grew_large2 + t)), _mm_cmpgt_ps(s2, _mm_loadu_ps(s.grew_small2 + t))));
        any = _mm_or_ps(any, _mm_or_ps(_mm_cmpgt_ps(l2, _mm_mul_ps(v_grow2, ref2)), _mm_cmpgt_ps(s2, _mm_mul_ps(v_unsquash2, ref_squeeze2))));
        any = _mm_or_ps(any, _mm_or_ps(_mm_cmplt_ps(l2, _mm_mul_ps(v_shrink2, ref2)), _mm_cmplt_ps(s2, _mm_mul_ps(v_squash2, ref_squeeze2))));
        // NaN (a broken simulation) compares false everywhere: take the per-triangle path too.
        any = _mm_or_ps(any, _mm_cmpunord_ps(l2, s2));
        append(busy, t, uint32_t(_mm_movemask_ps(any)) | counting(s.beyond + t, 4));
    }
    return t;
}
#endif

#if defined(PBDSPLAT_EIGHT_LANES)
// The eight-lane helpers and scan are compiled for AVX alone, each its own function (a lambda
// would not inherit the target), and no FMA: a fused multiply-add would round differently from
// the four-lane scan.
#define PBDSPLAT_AVX __attribute__((target("avx"), always_inline)) inline
PBDSPLAT_AVX __m256 pair(const float* low, const float* high) {
    return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(low)), _mm_loadu_ps(high), 1);
}
// Rows hold (x, y, z, w) of four triangles' edges in each half: x, y, z into r[0], r[1], r[2].
PBDSPLAT_AVX void transpose(__m256* r) {
    const __m256 t0 = _mm256_unpacklo_ps(r[0], r[1]), t1 = _mm256_unpackhi_ps(r[0], r[1]);
    const __m256 t2 = _mm256_unpacklo_ps(r[2], r[3]), t3 = _mm256_unpackhi_ps(r[2], r[3]);
    r[0] = _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(1, 0, 1, 0));
    r[1] = _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(3, 2, 3, 2));
    r[2] = _mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(1, 0, 1, 0));
}
PBDSPLAT_AVX __m256 dot(const __m256* u, const __m256* v) {
    return _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(u[0], v[0]), _mm256_mul_ps(u[1], v[1])), _mm256_mul_ps(u[2], v[2]));
}
// (p, q) G (p, q)^T, in the four-lane scan's order.
PBDSPLAT_AVX __m256 form(__m256 p, __m256 q, __m256 g11, __m256 g12, __m256 g22) {
    return _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(_mm256_mul_ps(p, p), g11), _mm256_mul_ps(_mm256_mul_ps(_mm256_set1_ps(2.0f), _mm256_mul_ps(p, q)), g12)),
                         _mm256_mul_ps(_mm256_mul_ps(q, q), g22));
}
PBDSPLAT_AVX __m256 lt(__m256 p, __m256 q) { return _mm256_cmp_ps(p, q, _CMP_LT_OS); }
PBDSPLAT_AVX __m256 gt(__m256 p, __m256 q) { return _mm256_cmp_ps(p, q, _CMP_GT_OS); }

// The four-lane scan's steps on two blocks of four at a time: row k holds triangle t + k in its
// low half and t + 4 + k in its high half, so after the transpose triangle t + j is in lane j.
__attribute__((target("avx"))) size_t scan_eight(const StretchScan& s, std::vector<uint32_t>& busy) {
    const __m256 v_grow2 = _mm256_set1_ps(s.grow2), v_shrink2 = _mm256_set1_ps(s.shrink2);
    const __m256 v_squash2 = _mm256_set1_ps(s.squash2), v_unsquash2 = _mm256_set1_ps(s.unsquash2);
    const __m256 v_tiny = _mm256_set1_ps(1e-12f), v_zero = _mm256_setzero_ps(), v_half = _mm256_set1_ps(0.5f);
    const size_t n = s.triangles.size();
    size_t t = 0;
    for (; t + 8 <= n; t += 8) {
        __m256 e1[4], e2[4];
        for (size_t k = 0; k < 4; ++k) {
            const mesh::Triangle& lo = s.triangles[t + k];
            const mesh::Triangle& hi = s.triangles[t + 4 + k];
            const __m256 o = pair(s.x[lo[0]].data(), s.x[hi[0]].data());
            e1[k] = _mm256_sub_ps(pair(s.x[lo[1]].data(), s.x[hi[1]].data()), o);
            e2[k] = _mm256_sub_ps(pair(s.x[lo[2]].data(), s.x[hi[2]].data()), o);
        }
        transpose(e1);
        transpose(e2);
        const float* rest = s.rest_lanes + 4 * t;  // two blocks of four
        const __m256 a = pair(rest, rest + 16), c = pair(rest + 4, rest + 20), b = pair(rest + 8, rest + 24), d = pair(rest + 12, rest + 28);
        const __m256 g11 = dot(e1, e1), g12 = dot(e1, e2), g22 = dot(e2, e2);
        const __m256 p11 = form(a, c, g11, g12, g22), p22 = form(b, d, g11, g12, g22);
        const __m256 p12 =
            _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(_mm256_mul_ps(a, b), g11), _mm256_mul_ps(_mm256_add_ps(_mm256_mul_ps(a, d), _mm256_mul_ps(b, c)), g12)),
                          _mm256_mul_ps(_mm256_mul_ps(c, d), g22));
        const __m256 half = _mm256_mul_ps(v_half, _mm256_add_ps(p11, p22)), diff = _mm256_mul_ps(v_half, _mm256_sub_ps(p11, p22));
        const __m256 root = _mm256_sqrt_ps(_mm256_add_ps(_mm256_mul_ps(diff, diff), _mm256_mul_ps(p12, p12)));
        const __m256 l2 = _mm256_add_ps(half, root), s2 = _mm256_max_ps(_mm256_sub_ps(half, root), v_zero);
        _mm256_storeu_ps(s.stretch2 + t, l2);
        _mm256_storeu_ps(s.squeeze2 + t, s2);
        const __m256 ref2 = _mm256_loadu_ps(s.reference2 + t);
        const __m256 ref_squeeze2 = _mm256_max_ps(_mm256_loadu_ps(s.reference_squeeze2 + t), v_tiny);
        __m256 any = _mm256_or_ps(lt(l2, _mm256_loadu_ps(s.shrank_large2 + t)), lt(s2, _mm256_loadu_ps(s.shrank_small2 + t)));
        any = _mm256_or_ps(any, _mm256_or_ps(gt(l2, _mm256_loadu_ps(s.grew_large2 + t)), gt(s2, _mm256_loadu_ps(s.grew_small2 + t))));
        any = _mm256_or_ps(any, _mm256_or_ps(gt(l2, _mm256_mul_ps(v_grow2, ref2)), gt(s2, _mm256_mul_ps(v_unsquash2, ref_squeeze2))));
        any = _mm256_or_ps(any, _mm256_or_ps(lt(l2, _mm256_mul_ps(v_shrink2, ref2)), lt(s2, _mm256_mul_ps(v_squash2, ref_squeeze2))));
        any = _mm256_or_ps(any, _mm256_cmp_ps(l2, s2, _CMP_UNORD_Q));
        append(busy, t, uint32_t(_mm256_movemask_ps(any)) | counting(s.beyond + t, 8));
    }
    return t;
}
#undef PBDSPLAT_AVX
#endif

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
    if (lanes != ScanLanes::four && eight_lanes_available()) t = stretch_scan_lanes::scan_eight(s, busy);
#else
    (void)lanes;
#endif
    return stretch_scan_lanes::scan_four(s, t, busy);
#else
    (void)s, (void)busy, (void)lanes;
    return 0;
#endif
}

} // namespace pbdsplat::surface
