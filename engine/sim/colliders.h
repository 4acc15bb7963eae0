#pragma once
// Static collision shapes of a scene. Particles are pushed out along the surface normal;
// friction removes tangential motion in proportion to the depth resolved (position-based Coulomb
// friction: the depth stands for the normal impulse).
#include <algorithm>
#include <optional>
#include <vector>

#include "core/math.h"

namespace pbdsplat::sim {

// The friction model of every contact, colliders and moving pieces alike: tangential motion
// below static_ x depth is removed whole (the particle sticks), above it kinetic x depth of it is.
struct Friction {
    float kinetic = 0.4f;
    float static_ = 0.4f;
};
// The share of tangential motion t that friction removes after a contact resolved `depth`.
template <class Real>
Real friction_share(const Friction& f, Real t, Real depth) {
    if (t <= Real(f.static_) * depth) return Real(1);
    return t > Real(0) ? std::min(Real(1), Real(f.kinetic) * depth / t) : Real(0);
}

struct GroundPlane {
    Vec3f normal{0.0f, 1.0f, 0.0f};  // unit, pointing into free space
    float offset = 0.0f;             // plane: dot(normal, x) = offset
};

struct SphereCollider {
    Vec3f center = Vec3f::Zero();
    float radius = 1.0f;
};

struct BoxCollider {
    Vec3f center = Vec3f::Zero();
    Vec3f half_extents = Vec3f::Constant(0.5f);
    Quatf rotation = Quatf::Identity();
};

struct Colliders {
    std::optional<GroundPlane> ground;
    std::vector<SphereCollider> spheres;
    std::vector<BoxCollider> boxes;
    Friction friction;
    bool empty() const { return !ground && spheres.empty() && boxes.empty(); }
};

} // namespace pbdsplat::sim
