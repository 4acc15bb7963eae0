#include <doctest/doctest.h>

#include "mesh/procedural.h"
#include "scene/scene_runtime.h"
#include "sim/shape.h"
#include "sim/pose.h"
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
        CHECK(sim::shape_report(b).max_error > 0.05);  // a squash to half height: far past a rigid motions 1e-6
    }

    TEST_CASE("edge stretch: 1 at rest and under a rigid motion, the ratio of a pulled particle's edges") {
        auto body = sim::make_soft_body(mesh::icosphere(3), {});
        REQUIRE(body.ok());
        sim::SoftBody b = std::move(body.value());
        CHECK(sim::edge_stretch_max(b) == doctest::Approx(1.0).epsilon(1e-5));
        const Mat3f r = Eigen::AngleAxisf(0.7f, Vec3f(0, 1, 1).normalized()).toRotationMatrix();
        for (auto& x : b.particles.x) x = sim::to4(r * sim::xyz(x) + Vec3f(1, 2, 3));
        CHECK(sim::edge_stretch_max(b) == doctest::Approx(1.0).epsilon(1e-5));
        // The whole body blown up twice about its centre reads 2.
        const auto rest = b.particles.x;
        for (auto& x : b.particles.x) x = sim::to4(Vec3f(1, 2, 3) + 2.0f * (sim::xyz(x) - Vec3f(1, 2, 3)));
        CHECK(sim::edge_stretch_max(b) == doctest::Approx(2.0).epsilon(1e-4));
        b.particles.x = rest;
        // One particle pulled out along its own direction from the centre: its edges, nearly
        // perpendicular to the pull at rest, grow to about the pull's length.
        const Vec3f centre = Vec3f(1, 2, 3);
        const Vec3f out = (sim::xyz(b.particles.x[0]) - centre).normalized();
        float rest_edge = 0.0f;
        for (const auto& c : b.distance)
            if (c.i == 0 || c.j == 0) rest_edge = std::max(rest_edge, c.rest);
        b.particles.x[0] = sim::to4(sim::xyz(b.particles.x[0]) + out * (10.0f * rest_edge));
        const double stretch = sim::edge_stretch_max(b);
        CHECK(stretch > 9.0);   // sqrt(10^2 + ~1) over rest, a rest edge at most the mean: about 10
        CHECK(stretch < 11.5);  // and not more: the other edges stay at 1
    }

    TEST_CASE("a body resting on the ground keeps its shape with shape matching, and sags without") {
        // No volume constraint either: shape matching alone must hold the shell up.
        const double sagged = resting_shape_error(0.0f, false, 2.0f);
        const double kept = resting_shape_error(scene::k_default_shape_stiffness, false, 2.0f);
        CHECK(kept < 0.05);  // measured 0.0077 (0.37 without)
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
        CHECK(sim::shape_report(b).max_error < 0.1 * before);  // five projections at 0.5 leave 1/32 of it
        CHECK((centre - after_centre).norm() / float(b.particle_count()) < 1e-4f);
    }
}

namespace {
// The procedural quadruped (legs 1/7 of its height thick) dropped 5 cm onto the ground at the
// scene defaults but for the shape stiffness; its pose after `seconds`.
sim::PoseReport quadruped_pose(float shape_stiffness, float seconds) {
    scene::Scene sc;
    sc.model.mesh = "quadruped:4";
    sc.model.translate = Vec3f(0.0f, 0.05f, 0.0f);
    sc.simulation.solver.shape_stiffness = shape_stiffness;
    sc.simulation.colliders.ground = sim::GroundPlane{Vec3f::UnitY(), -0.5f};
    auto rt = scene::SceneRuntime::create(sc, {});
    REQUIRE(rt.ok());
    for (int f = 0; f < int(seconds / sc.simulation.dt + 0.5f); ++f) REQUIRE(rt.value()->step().ok());
    const sim::PoseReport pose = sim::pose_report(rt.value()->body());
    MESSAGE("shape stiffness " << shape_stiffness << ": tilt " << pose.tilt_max_degrees << " degrees, height " << pose.height_ratio_min << " of rest");
    return pose;
}

// A square beam 1 long and 0.1 thick along x, its left tenth pinned, under gravity for 2 s at the
// scene defaults but for the shape stiffness: how far its free end hangs below where it was,
// over its length.
double cantilever_sag(float shape_stiffness) {
    mesh::TriangleMesh beam = mesh::box(Vec3f(1.0f, 0.1f, 0.1f), 20);
    sim::SoftBodyDesc desc;
    desc.shape_matching = true;
    auto made = sim::make_soft_body(std::move(beam), desc);
    REQUIRE(made.ok());
    sim::SoftBody b = std::move(made.value());
    for (uint32_t i = 0; i < b.particle_count(); ++i)
        if (b.particles.x[i].x() < -0.4f) b.pin(i);
    sim::rebuild_shape_clusters(b);
    const uint32_t tip = b.extreme_particle(0, true);
    const float start = b.particles.x[tip].y();
    sim::Solver solver;
    sim::SolverSettings settings = scene::default_scene_solver();
    settings.shape_stiffness = shape_stiffness;
    for (int f = 0; f < 120; ++f) solver.step(b, 1.0f / 60.0f, settings, {}, {});
    const double sag = double(start - b.particles.x[tip].y());
    MESSAGE("shape stiffness " << shape_stiffness << ": the free end sags " << sag << " of the length");
    return sag;
}
} // namespace

TEST_SUITE("sim/shape") {
    TEST_CASE("pose: a tilt turns the vertical, a turn about it does not; a squash shows in the height") {
        auto body = sim::make_soft_body(mesh::quadruped(1), {});
        REQUIRE(body.ok());
        sim::SoftBody b = std::move(body.value());
        const auto turned = [&](const Mat3f& r) {
            sim::SoftBody c = b;
            for (auto& x : c.particles.x) x = sim::to4(r * sim::xyz(x) + Vec3f(3, 1, -2));
            return sim::pose_report(c);
        };
        const sim::PoseReport tipped = turned(Eigen::AngleAxisf(math::radians(30.0f), Vec3f::UnitX()).toRotationMatrix());
        CHECK(tipped.tilt_max_degrees == doctest::Approx(30.0).epsilon(1e-3));
        const sim::PoseReport spun = turned(Eigen::AngleAxisf(math::radians(50.0f), Vec3f::UnitY()).toRotationMatrix());
        CHECK(spun.tilt_max_degrees < 1e-3);
        CHECK(spun.height_ratio_min == doctest::Approx(1.0).epsilon(1e-5));
        // A squashed box (symmetric, so its best fit is no turn at all): half its height.
        auto box = sim::make_soft_body(mesh::box(Vec3f(1, 1, 1), 2), {});
        REQUIRE(box.ok());
        for (auto& x : box.value().particles.x) x.y() *= 0.5f;
        CHECK(sim::pose_report(box.value()).height_ratio_min == doctest::Approx(0.5).epsilon(1e-5));
        CHECK(sim::pose_report(box.value()).tilt_max_degrees < 1e-3);
    }

    TEST_CASE("the smallest piece is counted in triangles") {
        mesh::TriangleMesh m = mesh::icosphere(1);  // 80 triangles
        mesh::append(m, mesh::box(Vec3f(1, 1, 1), 1), Eigen::Affine3f(Eigen::Translation3f(4, 0, 0)));  // 12
        auto body = sim::make_soft_body(std::move(m), {});
        REQUIRE(body.ok());
        CHECK(body.value().pieces == 2);
        CHECK(sim::smallest_piece_triangles(body.value()) == 12);
    }

    TEST_CASE("a four-legged body dropped on the ground stands on its thin legs at the default shape stiffness") {
        const sim::PoseReport held = quadruped_pose(scene::k_default_shape_stiffness, 2.0f);
        CHECK(held.tilt_max_degrees <= 10.0);  // the goal (docs/BENCHMARKS.md, Solids that stand); measured 2.4
        CHECK(held.height_ratio_min >= 0.9);  // the goal; measured 0.95
        // The earlier default, 0.3: the legs fold on landing and the body rocks (11.7 degrees,
        // 0.78 of its height measured): the check has teeth.
        const sim::PoseReport soft = quadruped_pose(0.3f, 2.0f);
        CHECK((soft.tilt_max_degrees > 10.0 || soft.height_ratio_min < 0.9));  // the goals bounds; measured 11.7 degrees, 0.85
    }

    TEST_CASE("a cantilevered beam holds itself out under gravity") {
        const double held = cantilever_sag(scene::k_default_shape_stiffness);
        CHECK(held < 0.05);  // measured 0.017 of the length
        CHECK(held < 0.5 * cantilever_sag(0.3f));  // measured 0.017 against 0.096
    }
}
