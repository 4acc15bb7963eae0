#pragma once
// Small bodies and a frame loop shared by the sim suites.
#include <doctest/doctest.h>

#include "mesh/procedural.h"
#include "sim/solver.h"
#include "support/why.h"

namespace pbdsplat::test {

inline sim::SoftBody make_body(mesh::TriangleMesh m, sim::SoftBodyDesc desc = {}) {
    auto b = sim::make_soft_body(std::move(m), desc);
    REQUIRE_MESSAGE(b.ok(), test::why(b));
    return std::move(b).value();
}

inline double total_mass(const sim::SoftBody& b) {
    double m = 0.0;
    for (float w : b.particles.w) m += w > 0.0f ? 1.0 / double(w) : 0.0;
    return m;
}

inline bool all_finite(const sim::SoftBody& b) {
    for (size_t i = 0; i < b.particle_count(); ++i)
        if (!b.particles.x[i].allFinite() || !b.particles.v[i].allFinite()) return false;
    return true;
}

inline void run(sim::SoftBody& b, int frames, float dt, const sim::SolverSettings& s, const sim::Colliders& c = {}) {
    sim::Solver solver;
    for (int f = 0; f < frames; ++f) solver.step(b, dt, s, c, sim::DragConstraint{});
}

} // namespace pbdsplat::test
