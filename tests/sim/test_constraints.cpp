#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include "sim/distance.h"
#include "sim/volume.h"
#include "sim_fixtures.h"

using namespace pbdsplat;

TEST_SUITE("sim/constraints") {
    TEST_CASE("a single pair projects to its rest length, heavier particle moving less") {
        sim::Particles p;
        p.resize(2);
        p.x[0] = Vec4f(0, 0, 0, 0);
        p.x[1] = Vec4f(2, 0, 0, 0);
        p.w = {1.0f, 3.0f};
        const sim::DistanceConstraint c{0, 1, 1.0f, 0.0f};
        sim::project_distance_pbd({&c, 1}, p, 1.0f);
        CHECK((p.x[1] - p.x[0]).norm() == doctest::Approx(1.0f));
        CHECK(p.x[0].x() == doctest::Approx(0.25f));  // moves w0 / (w0 + w1) of the error
        CHECK(p.x[1].x() == doctest::Approx(1.25f));
        // XPBD with zero compliance does the same.
        p.x[0] = Vec4f(0, 0, 0, 0);
        p.x[1] = Vec4f(2, 0, 0, 0);
        float lambda = 0.0f;
        sim::project_distance_xpbd({&c, 1}, {&lambda, 1}, p, 3600.0f);
        CHECK((p.x[1] - p.x[0]).norm() == doctest::Approx(1.0f));
    }

    TEST_CASE("pinned particles do not move") {
        sim::Particles p;
        p.resize(2);
        p.x[1] = Vec4f(3, 0, 0, 0);
        p.w = {0.0f, 1.0f};
        const sim::DistanceConstraint c{0, 1, 1.0f, 0.0f};
        sim::project_distance_pbd({&c, 1}, p, 1.0f);
        CHECK(p.x[0].norm() == 0.0f);
        CHECK(p.x[1].x() == doctest::Approx(1.0f));
    }

    TEST_CASE("volume: unit cube, fine icosphere, and origin independence with caps") {
        auto cube = test::make_body(mesh::box(Vec3f(1, 1, 1), 2));
        REQUIRE(cube.volumes.size() == 1);
        CHECK(cube.volume(0) == doctest::Approx(1.0).epsilon(1e-6));

        auto sphere = test::make_body(mesh::icosphere(5));
        const double analytic = 4.0 / 3.0 * M_PI;
        CHECK(sphere.volume(0) == doctest::Approx(analytic).epsilon(0.002));

        // An open box (top removed) far from the origin: the virtual cap closes it.
        auto open = mesh::box(Vec3f(1, 1, 1), 2);
        std::erase_if(open.triangles, [&](const mesh::Triangle& t) {
            return open.positions[t[0]].y() > 0.49f && open.positions[t[1]].y() > 0.49f && open.positions[t[2]].y() > 0.49f;
        });
        for (auto& p : open.positions) p += Vec3f(40, -25, 13);
        auto body = test::make_body(open);
        REQUIRE(body.volumes.size() == 1);
        CHECK(body.volumes[0].cap_loops.size() == 1);
        CHECK(body.volume(0) == doctest::Approx(1.0).epsilon(1e-4));
    }

    TEST_CASE("one volume projection restores the target volume to first order") {
        auto b = test::make_body(mesh::icosphere(3));
        for (auto& x : b.particles.x) x *= 0.9f;  // squeeze: 0.729 V0
        sim::Vec4Array scratch(b.particle_count(), Vec4f::Zero());
        sim::solve_volumes(b, scratch, false, 1.0f, 0.0f);
        CHECK(b.volume(0) / b.volumes[0].rest_volume == doctest::Approx(1.0).epsilon(0.02));
        for (int k = 0; k < 3; ++k) sim::solve_volumes(b, scratch, false, 1.0f, 0.0f);
        CHECK(b.volume(0) / b.volumes[0].rest_volume == doctest::Approx(1.0).epsilon(1e-5));
        // The pressure factor sets the target.
        b.volumes[0].pressure = 0.5f;
        for (int k = 0; k < 4; ++k) sim::solve_volumes(b, scratch, false, 1.0f, 0.0f);
        CHECK(b.volume(0) / b.volumes[0].rest_volume == doctest::Approx(0.5).epsilon(1e-4));
    }

    TEST_CASE("the volume pass projects every piece at once, as if one after another") {
        // Two spheres apart in one body, each with its own target: one pass over the particles
        // serves both, and each piece's constraint moves only its own particles.
        mesh::TriangleMesh two = mesh::icosphere(3);
        const mesh::TriangleMesh other = mesh::icosphere(2);
        const uint32_t offset = uint32_t(two.positions.size());
        for (const Vec3f& p : other.positions) two.positions.push_back(0.5f * p + Vec3f(4, 0, 0));
        for (const auto& t : other.triangles) two.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
        auto b = test::make_body(two);
        REQUIRE(b.pieces == 2);
        REQUIRE(b.volumes.size() == 2);
        CHECK(b.volumes[0].piece != b.volumes[1].piece);
        b.volumes[0].pressure = 0.7f;
        b.volumes[1].pressure = 1.3f;
        const sim::Vec4Array before = b.particles.x;
        sim::Vec4Array scratch(b.particle_count(), Vec4f::Zero());
        for (int k = 0; k < 6; ++k) sim::solve_volumes(b, scratch, false, 1.0f, 0.0f);
        CHECK(b.volume(0) / b.volumes[0].rest_volume == doctest::Approx(0.7).epsilon(1e-4));
        CHECK(b.volume(1) / b.volumes[1].rest_volume == doctest::Approx(1.3).epsilon(1e-4));
        // A piece that is done leaking is left out: its particles do not move.
        b.particles.x = before;
        b.volumes[1].pressure = 1.01f;
        b.volumes[1].leak = 1.0f;
        sim::solve_volumes(b, scratch, false, 1.0f, 0.0f);
        for (size_t i = 0; i < b.particle_count(); ++i)
            if (b.piece_of_particle[i] == b.volumes[1].piece) REQUIRE(b.particles.x[i] == before[i]);
    }
}
