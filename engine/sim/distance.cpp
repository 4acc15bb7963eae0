#include "sim/distance.h"

#include <cmath>
#include <type_traits>

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

namespace pbdsplat::sim {

namespace {
// The same arithmetic as the generic loop, kept in registers: Eigen's reductions on SSE2 go
// through memory and stall this loop. Returns false where SSE is not available.
bool project_distance_pbd_sse(std::span<const DistanceConstraint> constraints, Particles& p, float stiffness) {
#if defined(__SSE__)
    const float* w = p.w.data();
    float* xs = p.x.data()->data();
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
    return true;
#else
    (void)constraints, (void)p, (void)stiffness;
    return false;
#endif
}
} // namespace

template <class Real>
void project_distance_pbd(std::span<const DistanceConstraint> constraints, ParticlesT<Real>& p, Real stiffness) {
    if constexpr (std::is_same_v<Real, float>)
        if (project_distance_pbd_sse(constraints, p, stiffness)) return;
    Vec4<Real>* x = p.x.data();
    const Real* w = p.w.data();
    for (const DistanceConstraint& c : constraints) {
        const Real wi = w[c.i], wj = w[c.j];
        const Real wsum = wi + wj;
        if (wsum == Real(0)) continue;
        const Vec4<Real> d = x[c.i] - x[c.j];
        const Real len2 = d.squaredNorm();
        if (len2 < Real(1e-24)) continue;  // coincident: no direction to push along
        const Real len = std::sqrt(len2);
        const Vec4<Real> corr = (stiffness * (len - Real(c.rest)) / (len * wsum)) * d;
        x[c.i] -= wi * corr;
        x[c.j] += wj * corr;
    }
}

template <class Real>
void project_distance_xpbd(std::span<const DistanceConstraint> constraints, std::span<Real> lambda, ParticlesT<Real>& p,
                           Real inv_dt2) {
    Vec4<Real>* x = p.x.data();
    const Real* w = p.w.data();
    for (size_t k = 0; k < constraints.size(); ++k) {
        const DistanceConstraint& c = constraints[k];
        const Real wi = w[c.i], wj = w[c.j];
        const Real alpha = Real(c.compliance) * inv_dt2;
        const Real wsum = wi + wj;
        if (wsum + alpha == Real(0)) continue;
        const Vec4<Real> d = x[c.i] - x[c.j];
        const Real len2 = d.squaredNorm();
        if (len2 < Real(1e-24)) continue;
        const Real len = std::sqrt(len2);
        const Real C = len - Real(c.rest);
        const Real dlambda = (-C - alpha * lambda[k]) / (wsum + alpha);
        lambda[k] += dlambda;
        const Vec4<Real> corr = (dlambda / len) * d;
        x[c.i] += wi * corr;
        x[c.j] -= wj * corr;
    }
}

template void project_distance_pbd<float>(std::span<const DistanceConstraint>, ParticlesT<float>&, float);
template void project_distance_pbd<double>(std::span<const DistanceConstraint>, ParticlesT<double>&, double);
template void project_distance_xpbd<float>(std::span<const DistanceConstraint>, std::span<float>, ParticlesT<float>&, float);
template void project_distance_xpbd<double>(std::span<const DistanceConstraint>, std::span<double>, ParticlesT<double>&,
                                            double);

} // namespace pbdsplat::sim
