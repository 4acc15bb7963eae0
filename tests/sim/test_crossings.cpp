#include <doctest/doctest.h>

#include "mesh/procedural.h"
#include "sim/crossings.h"
#include "sim/sim_fixtures.h"
#include "topology/cut.h"

#include <limits>

using namespace pbdsplat;
using test::move_piece;

TEST_SUITE("sim/crossings") {
    TEST_CASE("two boxes: none apart or touching, some once one is pushed into the other, none within one piece") {
        sim::SoftBody b = test::two_boxes_at_rest({3.0f, 0.0f, 0.0f});
        CHECK(sim::surface_crossings(b).pairs == 0);
        const uint32_t right = b.piece_of_particle[b.extreme_particle(0, true)];
        // Face to face (x = 0.5): coplanar faces touch, they do not cross.
        move_piece(b, right, Vec3f(-2.0f, 0.0f, 0.0f));
        CHECK(sim::surface_crossings(b).pairs == 0);
        // 0.3 into it and a little off its axis (in line, the side walls would be coplanar): the
        // side walls of each pass through the other's facing wall.
        move_piece(b, right, Vec3f(-0.3f, 0.17f, 0.11f));
        const sim::Crossings c = sim::surface_crossings(b);
        MESSAGE("pushed 0.3 in: " << c.pairs << " pairs, " << c.triangles << " triangles of " << b.triangles.size());
        CHECK(c.pairs > 0);
        CHECK(c.self_pairs == 0);
        CHECK(c.ratio > 0.0);
        CHECK(c.ratio < 1.0);  // 28 of 96 measured: the walls only
    }

    TEST_CASE("parts that cross at rest do not count") {
        CHECK(sim::surface_crossings(test::two_boxes_at_rest({0.7f, 0.2f, 0.1f})).pairs == 0);
    }

    TEST_CASE("a ball with one vertex pushed out through its far side crosses itself") {
        sim::SoftBody b = test::make_body(mesh::icosphere(2, 1.0f));
        CHECK(sim::surface_crossings(b).pairs == 0);
        const uint32_t top = b.extreme_particle(1, true);
        // Off the sphere's planes of symmetry, where the moved edges would pass exactly
        // through edges and corners of the far side (touching, not crossing).
        b.particles.x[top] = sim::to4(Vec3f(0.13f, -1.5f, 0.21f));
        const sim::Crossings c = sim::surface_crossings(b);
        MESSAGE(c.pairs << " pairs");
        CHECK(c.self_pairs > 0);
        CHECK(c.self_pairs == c.pairs);
        // Only the fan of the moved vertex and the triangles it passes: a small share.
        CHECK(c.ratio < 0.1);
    }

    TEST_CASE("the two sides of a cut, resting as cut, do not cross; pushed into each other they do") {
        sim::SoftBody b = test::make_body(mesh::icosphere(3, 0.5f));
        test::cut_in_two(b, Vec3f(0.0f, 0.1f, 0.0f), Vec3f(0.3f, 1.0f, 0.0f));
        CHECK(sim::surface_crossings(b).pairs == 0);
        // Two edges deep: the triangles along the rim (which share rest places with the other
        // side's) are left out, the next rings are not.
        move_piece(b, b.piece_of_particle[b.extreme_particle(1, true)], -0.3f * Vec3f(0.3f, 1.0f, 0.0f).normalized());
        const sim::Crossings c = sim::surface_crossings(b);
        CHECK(c.pairs > 0);
        CHECK(c.self_pairs == 0);
    }

    TEST_CASE("models placed into each other at load are named, pair by pair; models apart are not") {
        sim::SoftBody into = test::two_boxes_at_rest({0.7f, 0.2f, 0.1f});
        into.model_of_particle = into.piece_of_particle;
        const std::vector<sim::ModelOverlap> o = sim::models_crossing_at_rest(into);
        REQUIRE(o.size() == 1);
        CHECK(o[0].a == 0);
        CHECK(o[0].b == 1);
        CHECK(o[0].pairs > 0);
        sim::SoftBody apart = test::two_boxes_at_rest({1.5f, 0.0f, 0.0f});
        apart.model_of_particle = apart.piece_of_particle;
        CHECK(sim::models_crossing_at_rest(apart).empty());
        // Parts of one model (a lid in its pot) are its own business.
        into.model_of_particle.assign(into.particle_count(), 0);
        CHECK(sim::models_crossing_at_rest(into).empty());
    }

    TEST_CASE("a body blown up (a particle not finite, one far out) is measured without it") {
        sim::SoftBody b = test::make_body(mesh::icosphere(2, 1.0f));
        b.particles.x[0] = sim::to4(Vec3f(std::numeric_limits<float>::quiet_NaN(), 0.0f, 0.0f));
        // The rest of the ball crosses nothing (its triangles through the lost corner are left out).
        CHECK(sim::surface_crossings(b).pairs == 0);
        // A corner far out (past int's reach in grid cells) makes its triangles wide, tested
        // against every other rather than cast out of range.
        b.particles.x[1] = sim::to4(Vec3f(1e30f, 0.0f, 0.0f));
        const sim::Crossings c = sim::surface_crossings(b);
        CHECK(c.ratio >= 0.0);
        CHECK(c.ratio < 0.5);  // its fan's few triangles and what they pass at most
    }
}
