#include "sim/collision.h"

#include <algorithm>
#include <cmath>

namespace pbdsplat::sim {
namespace {

// Moves x out by `depth` along unit `n`, then removes tangential motion: all of it while it is
// below static x depth (sticking), else kinetic x depth of it (sliding).
template <class Real>
void resolve(Vec4<Real>& x, const Vec4<Real>& x_prev, const Vec3f& n, Real depth, const Friction& friction) {
    const Vec4<Real> n4 = to4<Real>(n);
    x += depth * n4;
    const Vec4<Real> motion = x - x_prev;
    const Vec4<Real> tangential = motion - motion.dot(n4) * n4;
    x -= friction_share(friction, tangential.norm(), depth) * tangential;
}

} // namespace

template <class Real>
void solve_collisions(const Colliders& colliders, ParticlesT<Real>& p, size_t begin, size_t end) {
    if (colliders.empty()) return;
    using V3 = Eigen::Matrix<Real, 3, 1>;
    const Friction& mu = colliders.friction;
    for (size_t i = begin; i < end; ++i) {
        if (p.w[i] == Real(0)) continue;
        Vec4<Real>& x = p.x[i];
        if (colliders.ground) {
            const Real d = colliders.ground->normal.template cast<Real>().dot(x.template head<3>()) - Real(colliders.ground->offset);
            if (d < Real(0)) resolve<Real>(x, p.x_prev[i], colliders.ground->normal, -d, mu);
        }
        for (const SphereCollider& s : colliders.spheres) {
            const V3 r = x.template head<3>() - s.center.template cast<Real>();
            const Real len = r.norm();
            if (len < Real(s.radius)) {
                const Vec3f normal = len > Real(1e-12) ? Vec3f((r / len).template cast<float>()) : Vec3f(0.0f, 1.0f, 0.0f);
                resolve<Real>(x, p.x_prev[i], normal, Real(s.radius) - len, mu);
            }
        }
        for (const BoxCollider& b : colliders.boxes) {
            const Vec3f local = b.rotation.conjugate() * (xyz(x) - b.center);
            const Vec3f gap = b.half_extents - local.cwiseAbs();  // > 0 on every axis: inside
            if ((gap.array() <= 0.0f).any()) continue;
            int axis = 0;  // leave through the nearest face
            if (gap.y() < gap[axis]) axis = 1;
            if (gap.z() < gap[axis]) axis = 2;
            Vec3f normal_local = Vec3f::Zero();
            normal_local[axis] = local[axis] >= 0.0f ? 1.0f : -1.0f;
            resolve<Real>(x, p.x_prev[i], b.rotation * normal_local, Real(gap[axis]), mu);
        }
    }
}

template void solve_collisions<float>(const Colliders&, ParticlesT<float>&, size_t, size_t);
template void solve_collisions<double>(const Colliders&, ParticlesT<double>&, size_t, size_t);

} // namespace pbdsplat::sim
