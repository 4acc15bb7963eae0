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

} // namespace pbdsplat::sim
