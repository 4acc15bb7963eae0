#include "sim/distance.h"

#include <cmath>

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

namespace pbdsplat::sim {

void project_distance_pbd(std::span<const DistanceConstraint> constraints, Particles& p, float stiffness) {
    Vec4f* x = p.x.data();
    const float* w = p.w.data();
#if defined(__SSE__)
    // The same arithmetic as the portable loop below, kept in registers: Eigen's reductions on
    // SSE2 go through memory and stall this loop.
    float* xs = x->data();
    const __m128 k = _mm_set1_ps(stiffness);
    for (const DistanceConstraint& c : constraints) {
        const float wi = w[c.i], wj = w[c.j];
        const float wsum = wi + wj;
        if (wsum == 0.0f) continue;
        float* pi = xs + 4 * size_t(c.i);
        float* pj = xs + 4 * size_t(c.j);
        const __m128 xi = _mm_load_ps(pi), xj = _mm_load_ps(pj);
        const __m128 d = _mm_sub_ps(xi, xj);
        __m128 dd = _mm_mul_ps(d, d);
        dd = _mm_add_ps(dd, _mm_movehl_ps(dd, dd));
        dd = _mm_add_ss(dd, _mm_shuffle_ps(dd, dd, 1));
        const float len2 = _mm_cvtss_f32(dd);
        if (len2 < 1e-24f) continue;  // coincident: no direction to push along
        const float len = std::sqrt(len2);
        const __m128 s = _mm_mul_ps(k, _mm_set1_ps((len - c.rest) / (len * wsum)));
        const __m128 corr = _mm_mul_ps(s, d);
        _mm_store_ps(pi, _mm_sub_ps(xi, _mm_mul_ps(_mm_set1_ps(wi), corr)));
        _mm_store_ps(pj, _mm_add_ps(xj, _mm_mul_ps(_mm_set1_ps(wj), corr)));
    }
    return;
#endif
    for (const DistanceConstraint& c : constraints) {
        const float wi = w[c.i], wj = w[c.j];
        const float wsum = wi + wj;
        if (wsum == 0.0f) continue;
        const Vec4f d = x[c.i] - x[c.j];
        const float len2 = d.squaredNorm();
        if (len2 < 1e-24f) continue;  // coincident: no direction to push along
        const float len = std::sqrt(len2);
        const Vec4f corr = (stiffness * (len - c.rest) / (len * wsum)) * d;
        x[c.i] -= wi * corr;
        x[c.j] += wj * corr;
    }
}

void project_distance_xpbd(std::span<const DistanceConstraint> constraints, std::span<float> lambda, Particles& p,
                           float inv_dt2) {
    Vec4f* x = p.x.data();
    const float* w = p.w.data();
    for (size_t k = 0; k < constraints.size(); ++k) {
        const DistanceConstraint& c = constraints[k];
        const float wi = w[c.i], wj = w[c.j];
        const float alpha = c.compliance * inv_dt2;
        const float wsum = wi + wj;
        if (wsum + alpha == 0.0f) continue;
        const Vec4f d = x[c.i] - x[c.j];
        const float len2 = d.squaredNorm();
        if (len2 < 1e-24f) continue;
        const float len = std::sqrt(len2);
        const float C = len - c.rest;
        const float dlambda = (-C - alpha * lambda[k]) / (wsum + alpha);
        lambda[k] += dlambda;
        const Vec4f corr = (dlambda / len) * d;
        x[c.i] += wi * corr;
        x[c.j] -= wj * corr;
    }
}

} // namespace pbdsplat::sim
