#include "sim/integrate.h"
#include "sim/vec4_ops.h"

#include <cmath>

namespace pbdsplat::sim {

void apply_external_forces(Particles& p, const Vec3f& gravity, float damping, float dt) {
    const Vec4f dv = dt * to4(gravity);
    const float keep = damping > 0.0f ? std::exp(-damping * dt) : 1.0f;
    const size_t n = p.size();
    for (size_t i = 0; i < n; ++i) {
        if (p.w[i] == 0.0f) continue;  // pinned particles do not move
        p.v[i] = (p.v[i] + dv) * keep;
    }
}

void predict_positions(Particles& p, float dt) {
    const size_t n = p.size();
    for (size_t i = 0; i < n; ++i) {
        p.x_prev[i] = p.x[i];
        p.x[i] += dt * p.v[i];
    }
}

void update_velocities(Particles& p, float dt) {
    const float inv = 1.0f / dt;
    const size_t n = p.size();
    for (size_t i = 0; i < n; ++i)  // pinned particles keep no velocity, even when dragged
        p.v[i] = p.w[i] > 0.0f ? Vec4f((p.x[i] - p.x_prev[i]) * inv) : Vec4f::Zero();
}

void update_normals(std::span<const mesh::Triangle> triangles, const Vec4Array& x, std::vector<Vec3f>& normals) {
    const size_t n = x.size();
    Vec4Array acc(n, Vec4f::Zero());
    for (const auto& t : triangles) {
        const Vec4f face = cross3(x[t[1]] - x[t[0]], x[t[2]] - x[t[0]]);  // twice the area, outward
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

} // namespace pbdsplat::sim
