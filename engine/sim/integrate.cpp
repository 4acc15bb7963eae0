#include "sim/integrate.h"

#include <cmath>

#include "sim/vec4_ops.h"

namespace pbdsplat::sim {

template <class Real>
void apply_forces_and_predict(ParticlesT<Real>& p, const Vec3f& gravity, float damping, Real dt, size_t begin, size_t end) {
    const Vec4<Real> dv = dt * to4<Real>(gravity);
    const Real keep = damping > 0.0f ? std::exp(-Real(damping) * dt) : Real(1);
    for (size_t i = begin; i < end; ++i) {
        if (p.w[i] != Real(0)) p.v[i] = (p.v[i] + dv) * keep;  // pinned particles do not move
        p.x_prev[i] = p.x[i];
        p.x[i] += dt * p.v[i];
    }
}

template <class Real>
void update_velocities(ParticlesT<Real>& p, Real dt, size_t begin, size_t end) {
    const Real inv = Real(1) / dt;
    for (size_t i = begin; i < end; ++i)
        p.v[i] = p.w[i] > Real(0) ? Vec4<Real>((p.x[i] - p.x_prev[i]) * inv) : Vec4<Real>::Zero();
}

VertexRings build_vertex_rings(std::span<const mesh::Triangle> triangles, size_t vertex_count) {
    VertexRings r;
    r.start.assign(vertex_count + 1, 0);
    for (const auto& t : triangles)
        for (uint32_t v : t) ++r.start[v + 1];
    for (size_t i = 0; i < vertex_count; ++i) r.start[i + 1] += r.start[i];
    r.ring.resize(r.start.back());
    std::vector<uint32_t> fill(r.start.begin(), r.start.end() - 1);
    for (const auto& t : triangles) {
        r.ring[fill[t[0]]++] = {t[1], t[2]};
        r.ring[fill[t[1]]++] = {t[2], t[0]};
        r.ring[fill[t[2]]++] = {t[0], t[1]};
    }
    return r;
}

void update_normals(const VertexRings& rings, const Vec4Array& x, std::vector<Vec3f>& normals, size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
        Vec4f acc = Vec4f::Zero();
        for (uint32_t r = rings.start[i]; r < rings.start[i + 1]; ++r)
            acc += cross3<float>(x[rings.ring[r][0]] - x[i], x[rings.ring[r][1]] - x[i]);  // twice the area, outward
        const float len = acc.norm();
        normals[i] = len > 0.0f ? Vec3f(acc.head<3>() / len) : Vec3f(0.0f, 1.0f, 0.0f);
    }
}

template void apply_forces_and_predict<float>(ParticlesT<float>&, const Vec3f&, float, float, size_t, size_t);
template void apply_forces_and_predict<double>(ParticlesT<double>&, const Vec3f&, float, double, size_t, size_t);
template void update_velocities<float>(ParticlesT<float>&, float, size_t, size_t);
template void update_velocities<double>(ParticlesT<double>&, double, size_t, size_t);

} // namespace pbdsplat::sim
