#include "sim/integrate.h"

#include <cmath>

#include "sim/vec4_ops.h"

namespace pbdsplat::sim {

template <class Real>
void apply_external_forces(ParticlesT<Real>& p, const Vec3f& gravity, float damping, Real dt) {
    const Vec4<Real> dv = dt * to4<Real>(gravity);
    const Real keep = damping > 0.0f ? std::exp(-Real(damping) * dt) : Real(1);
    const size_t n = p.size();
    for (size_t i = 0; i < n; ++i) {
        if (p.w[i] == Real(0)) continue;  // pinned particles do not move
        p.v[i] = (p.v[i] + dv) * keep;
    }
}

template <class Real>
void predict_positions(ParticlesT<Real>& p, Real dt) {
    const size_t n = p.size();
    for (size_t i = 0; i < n; ++i) {
        p.x_prev[i] = p.x[i];
        p.x[i] += dt * p.v[i];
    }
}

template <class Real>
void update_velocities(ParticlesT<Real>& p, Real dt) {
    const Real inv = Real(1) / dt;
    const size_t n = p.size();
    for (size_t i = 0; i < n; ++i)
        p.v[i] = p.w[i] > Real(0) ? Vec4<Real>((p.x[i] - p.x_prev[i]) * inv) : Vec4<Real>::Zero();
}

void update_normals(std::span<const mesh::Triangle> triangles, const Vec4Array& x, std::vector<Vec3f>& normals) {
    const size_t n = x.size();
    Vec4Array acc(n, Vec4f::Zero());
    for (const auto& t : triangles) {
        const Vec4f face = cross3<float>(x[t[1]] - x[t[0]], x[t[2]] - x[t[0]]);  // twice the area, outward
        acc[t[0]] += face;
        acc[t[1]] += face;
        acc[t[2]] += face;
    }
    normals.resize(n);
    for (size_t i = 0; i < n; ++i) {
        const float len = acc[i].norm();
        normals[i] = len > 0.0f ? Vec3f(acc[i].head<3>() / len) : Vec3f(0.0f, 1.0f, 0.0f);
    }
}

template void apply_external_forces<float>(ParticlesT<float>&, const Vec3f&, float, float);
template void apply_external_forces<double>(ParticlesT<double>&, const Vec3f&, float, double);
template void predict_positions<float>(ParticlesT<float>&, float);
template void predict_positions<double>(ParticlesT<double>&, double);
template void update_velocities<float>(ParticlesT<float>&, float);
template void update_velocities<double>(ParticlesT<double>&, double);

} // namespace pbdsplat::sim
