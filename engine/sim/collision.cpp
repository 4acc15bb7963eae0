#include "sim/collision.h"

#include <cmath>

namespace pbdsplat::sim {
namespace {

// Moves x out by `depth` along unit `n`, then removes tangential motion: all of it while it is
// below friction * depth (sticking), else that much of it (sliding).
void resolve(Vec4f& x, const Vec4f& x_prev, const Vec3f& n, float depth, float friction) {
    const Vec4f n4 = to4(n);
    x += depth * n4;
    const Vec4f motion = x - x_prev;
    const Vec4f tangential = motion - motion.dot(n4) * n4;
    const float t = tangential.norm();
    const float limit = friction * depth;
    if (t <= limit) x -= tangential;
    else if (t > 0.0f) x -= (limit / t) * tangential;
}

} // namespace

void solve_collisions(const Colliders& colliders, Particles& p) {
    if (colliders.empty()) return;
    const float mu = colliders.friction;
    const size_t n = p.size();
    for (size_t i = 0; i < n; ++i) {
        if (p.w[i] == 0.0f) continue;
        Vec4f& x = p.x[i];
        if (colliders.ground) {
            const float d = colliders.ground->normal.dot(xyz(x)) - colliders.ground->offset;
            if (d < 0.0f) resolve(x, p.x_prev[i], colliders.ground->normal, -d, mu);
        }
        for (const SphereCollider& s : colliders.spheres) {
            const Vec3f r = xyz(x) - s.center;
            const float len = r.norm();
            if (len < s.radius) {
                const Vec3f normal = len > 1e-12f ? Vec3f(r / len) : Vec3f(0.0f, 1.0f, 0.0f);
                resolve(x, p.x_prev[i], normal, s.radius - len, mu);
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
            resolve(x, p.x_prev[i], b.rotation * normal_local, gap[axis], mu);
        }
    }
}

} // namespace pbdsplat::sim
