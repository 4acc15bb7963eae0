#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "mesh/procedural.h"
#include "sim/approach.h"
#include "sim/sim_fixtures.h"

using namespace pbdsplat;

namespace {

// Two 0.4 m balls 0.5 m apart along x (0.1 m between them), as two models; the left one moving
// at `left`, the right at `right`.
sim::SoftBody two_balls(const Vec3f& left, const Vec3f& right) {
    mesh::TriangleMesh m = mesh::icosphere(2, 0.2f);
    mesh::append(m, mesh::icosphere(2, 0.2f), test::moved_by(Vec3f(0.5f, 0.0f, 0.0f)));
    sim::SoftBodyDesc d;
    d.shape_matching = true;
    sim::SoftBody b = test::make_body(std::move(m), d);
    b.model_of_particle = b.piece_of_particle;
    for (size_t i = 0; i < b.particle_count(); ++i) b.particles.v[i] = sim::to4(b.particles.x[i].x() < 0.25f ? left : right);
    return b;
}

} // namespace

TEST_SUITE("sim/approach") {
    TEST_CASE("substeps follow how fast two pieces close on each other, not how fast they move") {
        const float dt = 1.0f / 60.0f, edge = 0.05f;
        // Closing at 11 m/s: 0.18 m a frame (past the 0.1 m gap), 7.3 half edges: 8 substeps.
        CHECK(sim::approach_substeps(two_balls({11, 0, 0}, {0, 0, 0}), dt, edge, 16) == 8);
        // 13 m/s needs 8.7: the next power of two.
        CHECK(sim::approach_substeps(two_balls({13, 0, 0}, {0, 0, 0}), dt, edge, 16) == 16);
        CHECK(sim::approach_substeps(two_balls({40, 0, 0}, {0, 0, 0}), dt, edge, 16) == 16);  // at most `most`
        // Moving together, parting, or not meeting this frame (1 m/s: 0.017 m of the 0.1): one.
        CHECK(sim::approach_substeps(two_balls({12, 0, 0}, {12, 0, 0}), dt, edge, 16) == 1);
        CHECK(sim::approach_substeps(two_balls({-12, 0, 0}, {0, 0, 0}), dt, edge, 16) == 1);
        CHECK(sim::approach_substeps(two_balls({1, 0, 0}, {0, 0, 0}), dt, edge, 16) == 1);
    }
}
