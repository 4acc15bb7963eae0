#include "sim/distance.h"

#include <cmath>

namespace pbdsplat::sim {

void project_distance_pbd(std::span<const DistanceConstraint> constraints, Particles& p, float stiffness) {
    Vec4f* x = p.x.data();
    const float* w = p.w.data();
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
