#include "sim/distance.h"

#include <cmath>
#include <type_traits>

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

namespace pbdsplat::sim {

namespace {
#if defined(__SSE__)
// One constraint, the generic loop's arithmetic kept in registers: Eigen's reductions on SSE2 go
// through memory and stall this loop.
inline void project_one_sse(const DistanceConstraint& c, float* xs, const float* w, __m128 k) {
    const float wi = w[c.i], wj = w[c.j];
    const float wsum = wi + wj;
    if (wsum == 0.0f) return;
    float* pi = xs + 4 * size_t(c.i);
    float* pj = xs + 4 * size_t(c.j);
    const __m128 xi = _mm_load_ps(pi), xj = _mm_load_ps(pj);
    const __m128 d = _mm_sub_ps(xi, xj);
    __m128 dd = _mm_mul_ps(d, d);
    dd = _mm_add_ps(dd, _mm_movehl_ps(dd, dd));
    dd = _mm_add_ss(dd, _mm_shuffle_ps(dd, dd, 1));
    const float len2 = _mm_cvtss_f32(dd);
    if (len2 < 1e-24f) return;  // coincident: no direction to push along
    const float len = std::sqrt(len2);
    const __m128 s = _mm_mul_ps(k, _mm_set1_ps((len - c.rest) / (len * wsum)));
    const __m128 corr = _mm_mul_ps(s, d);
    _mm_store_ps(pi, _mm_sub_ps(xi, _mm_mul_ps(_mm_set1_ps(wi), corr)));
    _mm_store_ps(pj, _mm_add_ps(xj, _mm_mul_ps(_mm_set1_ps(wj), corr)));
}

// Four constraints of one colour at once (they share no particle): the particles transposed to
// one register per component, one packed sqrt and divide for the four. Every operation is the
// one-at-a-time loop's, in its order (|d|^2 as (x^2 + z^2) + (y^2 + w^2)), so the positions are
// the same to the bit. A lane the loop would skip (no mass, coincident) stores nothing; a dead
// slot (i == i) is coincident, and its particle may be one a live lane of the four moves.
inline void project_four_sse(const DistanceConstraint* c, float* xs, const float* w, __m128 k) {
    float* pi[4] = {xs + 4 * size_t(c[0].i), xs + 4 * size_t(c[1].i), xs + 4 * size_t(c[2].i), xs + 4 * size_t(c[3].i)};
    float* pj[4] = {xs + 4 * size_t(c[0].j), xs + 4 * size_t(c[1].j), xs + 4 * size_t(c[2].j), xs + 4 * size_t(c[3].j)};
    __m128 ax = _mm_load_ps(pi[0]), ay = _mm_load_ps(pi[1]), az = _mm_load_ps(pi[2]), aw = _mm_load_ps(pi[3]);
    __m128 bx = _mm_load_ps(pj[0]), by = _mm_load_ps(pj[1]), bz = _mm_load_ps(pj[2]), bw = _mm_load_ps(pj[3]);
    _MM_TRANSPOSE4_PS(ax, ay, az, aw);
    _MM_TRANSPOSE4_PS(bx, by, bz, bw);
    const __m128 wi = _mm_setr_ps(w[c[0].i], w[c[1].i], w[c[2].i], w[c[3].i]);
    const __m128 wj = _mm_setr_ps(w[c[0].j], w[c[1].j], w[c[2].j], w[c[3].j]);
    const __m128 rest = _mm_setr_ps(c[0].rest, c[1].rest, c[2].rest, c[3].rest);
    const __m128 wsum = _mm_add_ps(wi, wj);
    const __m128 dx = _mm_sub_ps(ax, bx), dy = _mm_sub_ps(ay, by), dz = _mm_sub_ps(az, bz), dw = _mm_sub_ps(aw, bw);
    const __m128 len2 = _mm_add_ps(_mm_add_ps(_mm_mul_ps(dx, dx), _mm_mul_ps(dz, dz)), _mm_add_ps(_mm_mul_ps(dy, dy), _mm_mul_ps(dw, dw)));
    // The loop's skips: wsum == 0, and len2 < 1e-24 (NaN goes on, as there).
    const __m128 go = _mm_and_ps(_mm_cmpneq_ps(wsum, _mm_setzero_ps()), _mm_cmpnlt_ps(len2, _mm_set1_ps(1e-24f)));
    const int store = _mm_movemask_ps(go);
    if (store == 0) return;
    const __m128 len = _mm_sqrt_ps(len2);
    const __m128 s = _mm_and_ps(go, _mm_mul_ps(k, _mm_div_ps(_mm_sub_ps(len, rest), _mm_mul_ps(len, wsum))));
    const __m128 cx = _mm_mul_ps(s, dx), cy = _mm_mul_ps(s, dy), cz = _mm_mul_ps(s, dz), cw = _mm_mul_ps(s, dw);
    ax = _mm_sub_ps(ax, _mm_mul_ps(wi, cx)), ay = _mm_sub_ps(ay, _mm_mul_ps(wi, cy));
    az = _mm_sub_ps(az, _mm_mul_ps(wi, cz)), aw = _mm_sub_ps(aw, _mm_mul_ps(wi, cw));
    bx = _mm_add_ps(bx, _mm_mul_ps(wj, cx)), by = _mm_add_ps(by, _mm_mul_ps(wj, cy));
    bz = _mm_add_ps(bz, _mm_mul_ps(wj, cz)), bw = _mm_add_ps(bw, _mm_mul_ps(wj, cw));
    _MM_TRANSPOSE4_PS(ax, ay, az, aw);
    _MM_TRANSPOSE4_PS(bx, by, bz, bw);
    const __m128 ra[4] = {ax, ay, az, aw}, rb[4] = {bx, by, bz, bw};
    for (int l = 0; l < 4; ++l)
        if (store >> l & 1) _mm_store_ps(pi[l], ra[l]), _mm_store_ps(pj[l], rb[l]);
}
#endif

// Returns false where SSE is not available. `constraints` lie inside one colour.
bool project_distance_pbd_sse(std::span<const DistanceConstraint> constraints, Particles& p, float stiffness) {
#if defined(__SSE__)
    const float* w = p.w.data();
    float* xs = p.x.data()->data();
    const __m128 k = _mm_set1_ps(stiffness);
    size_t n = 0;
    for (; n + 4 <= constraints.size(); n += 4) project_four_sse(constraints.data() + n, xs, w, k);
    for (; n < constraints.size(); ++n) project_one_sse(constraints[n], xs, w, k);
    return true;
#else
    (void)constraints, (void)p, (void)stiffness;
    return false;
#endif
}

bool project_distance_pbd_sse(std::span<const DistanceConstraint> constraints, std::span<const float> stiffness, Particles& p) {
#if defined(__SSE__)
    const float* w = p.w.data();
    float* xs = p.x.data()->data();
    size_t n = 0;
    for (; n + 4 <= constraints.size(); n += 4) project_four_sse(constraints.data() + n, xs, w, _mm_loadu_ps(stiffness.data() + n));
    for (; n < constraints.size(); ++n) project_one_sse(constraints[n], xs, w, _mm_set1_ps(stiffness[n]));
    return true;
#else
    (void)constraints, (void)stiffness, (void)p;
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
void project_distance_pbd(std::span<const DistanceConstraint> constraints, std::span<const Real> stiffness, ParticlesT<Real>& p) {
    if constexpr (std::is_same_v<Real, float>)
        if (project_distance_pbd_sse(constraints, stiffness, p)) return;
    for (size_t k = 0; k < constraints.size(); ++k) project_distance_pbd<Real>(constraints.subspan(k, 1), p, stiffness[k]);
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
template void project_distance_pbd<float>(std::span<const DistanceConstraint>, std::span<const float>, ParticlesT<float>&);
template void project_distance_pbd<double>(std::span<const DistanceConstraint>, std::span<const double>, ParticlesT<double>&);
template void project_distance_xpbd<float>(std::span<const DistanceConstraint>, std::span<float>, ParticlesT<float>&, float);
template void project_distance_xpbd<double>(std::span<const DistanceConstraint>, std::span<double>, ParticlesT<double>&,
                                            double);

} // namespace pbdsplat::sim
