#pragma once
// 4-vector helpers for the hot loops. Eigen's cross3 assembles its float result through the
// stack on SSE2, and the 16-byte reload then misses store forwarding (~15 cycles a call);
// shuffles keep it in registers.
#include <type_traits>

#include "sim/particles.h"

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

namespace pbdsplat::sim {

// Cross product of the xyz parts; w of the result is 0 when both w are 0.
template <class Real>
inline Vec4<Real> cross3(const Vec4<Real>& a, const Vec4<Real>& b) {
#if defined(__SSE__)
    if constexpr (std::is_same_v<Real, float>) {
        const __m128 va = _mm_load_ps(a.data()), vb = _mm_load_ps(b.data());
        const __m128 a_yzx = _mm_shuffle_ps(va, va, _MM_SHUFFLE(3, 0, 2, 1));
        const __m128 b_yzx = _mm_shuffle_ps(vb, vb, _MM_SHUFFLE(3, 0, 2, 1));
        const __m128 c = _mm_sub_ps(_mm_mul_ps(va, b_yzx), _mm_mul_ps(a_yzx, vb));
        Vec4<float> out;
        _mm_store_ps(out.data(), _mm_shuffle_ps(c, c, _MM_SHUFFLE(3, 0, 2, 1)));
        return out;
    }
#endif
    return a.cross3(b);
}

// The sum of the cross products a_k x b_k. The SSE cross product ends with a lane shuffle;
// summing the unshuffled products and shuffling once gives the same bits (a lane permutation
// commutes with lane-wise adds) and saves a shuffle per term.
template <class Real, class Pairs, class At>
inline Vec4<Real> sum_of_cross3(const Pairs& pairs, At&& at) {
#if defined(__SSE__)
    if constexpr (std::is_same_v<Real, float>) {
        __m128 acc = _mm_setzero_ps();
        for (const auto& pair : pairs) {
            const __m128 va = _mm_load_ps(at(pair[0]).data()), vb = _mm_load_ps(at(pair[1]).data());
            const __m128 a_yzx = _mm_shuffle_ps(va, va, _MM_SHUFFLE(3, 0, 2, 1));
            const __m128 b_yzx = _mm_shuffle_ps(vb, vb, _MM_SHUFFLE(3, 0, 2, 1));
            acc = _mm_add_ps(acc, _mm_sub_ps(_mm_mul_ps(va, b_yzx), _mm_mul_ps(a_yzx, vb)));
        }
        Vec4<float> out;
        _mm_store_ps(out.data(), _mm_shuffle_ps(acc, acc, _MM_SHUFFLE(3, 0, 2, 1)));
        return out;
    }
#endif
    Vec4<Real> g = Vec4<Real>::Zero();
    for (const auto& pair : pairs) g += cross3<Real>(at(pair[0]), at(pair[1]));
    return g;
}

} // namespace pbdsplat::sim
