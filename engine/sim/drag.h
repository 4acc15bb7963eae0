#pragma once
#include <optional>

#include "sim/constraints.h"
#include "sim/particles.h"

namespace pbdsplat::sim {

// The particle a ray (origin, unit direction) picks: among those within `radius` of the ray
// and in front of its origin, the nearest along it; none if no particle is that close.
std::optional<uint32_t> pick_particle(const Particles& p, const Vec3f& origin, const Vec3f& direction, float radius);

// Moves the dragged particle toward its target (pinned particles are moved too: a drag can
// reposition a pin).
template <class Real>
void solve_drag(const DragConstraint& drag, ParticlesT<Real>& p) {
    if (!drag.active || drag.particle >= p.size()) return;
    Vec4<Real>& x = p.x[drag.particle];
    x += Real(drag.stiffness) * (to4<Real>(drag.target) - x);
}

} // namespace pbdsplat::sim
