#include <doctest/doctest.h>

#include "mesh/procedural.h"
#include "scene/scene_runtime.h"
#include "sim/shape.h"
#include "sim/shape_error.h"
#include "sim/soft_body.h"
#include "sim/solver.h"

using namespace pbdsplat;

namespace {
// A capsule dropped on the ground for `seconds`: the worst piece's shape error at the end.
double resting_shape_error(float shape_stiffness, bool volume, float seconds) {
    scene::Scene sc;
    sc.model.mesh = "capsule:8:16";
    sc.simulation.solver.shape_stiffness = shape_stiffness;
    sc.simulation.solver.volume = volume;
    sc.simulation.solver.damping = 0.5f;
    sc.simulation.colliders.ground = sim::GroundPlane{Vec3f::UnitY(), -1.2f};
    auto rt = scene::SceneRuntime::create(sc, {});
    REQUIRE(rt.ok());
    for (int f = 0; f < int(seconds / sc.simulation.dt); ++f) REQUIRE(rt.value()->step().ok());
    const double e = sim::shape_report(rt.value()->body()).max_error;
    MESSAGE("shape stiffness " << shape_stiffness << ": shape error " << e);
    return e;
}
} // namespace

TEST_SUITE("sim/shape") {
    TEST_CASE("shape error: a rigid motion scores 0, a squash does not") {
        auto body = sim::make_soft_body(mesh::icosphere(3), {});
        REQUIRE(body.ok());
        sim::SoftBody b = std::move(body.value());
        const Mat3f r = Eigen::AngleAxisf(2.0f, Vec3f(1, 2, 3).normalized()).toRotationMatrix();
        for (auto& x : b.particles.x) x = sim::to4(r * sim::xyz(x) + Vec3f(4, -1, 2));
        CHECK(sim::shape_report(b).max_error < 1e-6);
        for (auto& x : b.particles.x) x.y() *= 0.5f;
        CHECK(sim::shape_report(b).max_error > 0.05);
    }

    TEST_CASE("a body resting on the ground keeps its shape with shape matching, and sags without") {
        // No volume constraint either: shape matching alone must hold the shell up.
        const double sagged = resting_shape_error(0.0f, false, 2.0f);
        const double kept = resting_shape_error(scene::k_default_shape_stiffness, false, 2.0f);
        CHECK(kept < 0.05);
        CHECK(sagged > 2.0 * kept);  // the same body without it: the check has teeth
    }

    TEST_CASE("shape matching restores a deformed piece toward its rest shape and keeps its centre") {
        auto body = sim::make_soft_body(mesh::icosphere(3), {});
        REQUIRE(body.ok());
        sim::SoftBody b = std::move(body.value());
        auto clusters = sim::build_shape_clusters(b.triangles, b.rest_positions, b.particles.w);
        REQUIRE(clusters.size() == 1);
        for (auto& x : b.particles.x) x.x() *= 1.4f;
        const double before = sim::shape_report(b).max_error;
        Vec4f centre = Vec4f::Zero();
        for (auto& x : b.particles.x) centre += x;
        for (int it = 0; it < 5; ++it) sim::project_shape<float>(clusters[0], b.particles, 0.5f, false, 0.0f);
        Vec4f after_centre = Vec4f::Zero();
        for (auto& x : b.particles.x) after_centre += x;
        CHECK(sim::shape_report(b).max_error < 0.1 * before);
        CHECK((centre - after_centre).norm() / float(b.particle_count()) < 1e-4f);
    }
}
