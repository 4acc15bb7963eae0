#pragma once
#include <optional>

#include "sim/constraints.h"
#include "sim/particles.h"
#include "sim/soft_body.h"

namespace pbdsplat::sim {

// The particle a ray (origin, unit direction) picks: among those within `radius` of the ray
// and in front of its origin, the nearest along it; none if no particle is that close.
std::optional<uint32_t> pick_particle(const Particles& p, const Vec3f& origin, const Vec3f& direction, float radius);

// The grab of the region of `centre`'s piece within `radius` of it (the centre alone when the
// radius is 0), pulled with `stiffness` (fraction of the gap per iteration) over the inner half
// and less toward the rim. The grab point is the centre particle's position. A piece whose every
// particle is pinned (a static body) is not grabbed: the drag is inactive.
DragConstraint grab_region(const SoftBody& body, uint32_t centre, float radius, float stiffness);

// A drag's radius when its scene or the demo does not say: two rest edges (four sampling
// spacings at the default eta), enough to hold a patch the size of a fingertip on the mesh.
float default_grab_radius(const SoftBody& body);

// Moves every held particle toward its place in the moved region (pinned particles are moved
// too: a drag can reposition a pin on a piece that is not pinned whole).
template <class Real>
void solve_drag(const DragConstraint& drag, ParticlesT<Real>& p) {
    if (!drag.active) return;
    for (size_t k = 0; k < drag.particles.size(); ++k) {
        const uint32_t i = drag.particles[k];
        if (i >= p.size()) continue;
        Vec4<Real>& x = p.x[i];
        x += Real(drag.weights[k]) * (to4<Real>(Vec3f(drag.target + drag.offsets[k])) - x);
    }
}

} // namespace pbdsplat::sim
