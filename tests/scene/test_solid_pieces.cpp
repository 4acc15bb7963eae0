#include <doctest/doctest.h>

#include <algorithm>

#include "mesh/procedural.h"
#include "scene/stages/solid_pieces.h"
#include "sim/sim_fixtures.h"
#include "topology/cut.h"

using namespace pbdsplat;

TEST_SUITE("scene/solid_pieces") {
    TEST_CASE("a sealed ball is solid; leaking, or cut with no face drawn over its cut, it is not") {
        sim::SoftBody b = test::make_body(mesh::icosphere(3, 0.5f));
        CHECK(scene::which_solid(scene::solid_pieces(b, nullptr)) == scene::Solids::all);
        b.volumes[0].leak = 0.5f;
        CHECK(scene::which_solid(scene::solid_pieces(b, nullptr)) == scene::Solids::none);
        sim::SoftBody cut = test::make_body(mesh::icosphere(3, 0.5f));
        auto plane = topology::plane_cut(Vec3f(0.0f, 0.1f, 0.0f), Vec3f(0.3f, 1.0f, 0.0f).normalized());
        REQUIRE(plane.ok());
        REQUIRE(topology::cut(cut, plane.value()).ok());
        REQUIRE(cut.pieces == 2);
        // Each half has a cap loop; no cut face is drawn over it, so its inside shows.
        CHECK(scene::which_solid(scene::solid_pieces(cut, nullptr)) == scene::Solids::none);
    }

    TEST_CASE("with a solid piece and an open one, the solid's triangles come first, the set unchanged") {
        sim::SoftBody b = test::two_boxes_at_rest({3.0f, 0.0f, 0.0f});
        const uint32_t open_piece = b.piece_of_particle[b.extreme_particle(0, true)];
        for (sim::VolumeConstraint& v : b.volumes)
            if (v.piece == open_piece) v.leak = 0.5f;
        REQUIRE(scene::which_solid(scene::solid_pieces(b, nullptr)) == scene::Solids::some);
        std::vector<mesh::Triangle> triangles = b.triangles;
        const scene::SolidOrder order = scene::order_solids_first(b, scene::solid_pieces(b, nullptr), triangles, nullptr);
        CHECK_FALSE(order.all);
        const size_t solid_count = size_t(std::count_if(b.triangles.begin(), b.triangles.end(),
                                                        [&](const mesh::Triangle& t) { return b.piece_of_particle[t[0]] != open_piece; }));
        CHECK(order.leading == solid_count);
        CHECK(order.one_sided(triangles.size() + 10) == solid_count);  // faces appended after are drawn both sides
        for (size_t k = 0; k < triangles.size(); ++k) CHECK((b.piece_of_particle[triangles[k][0]] != open_piece) == (k < solid_count));
        std::vector<mesh::Triangle> sorted_before = b.triangles, sorted_after = triangles;
        std::sort(sorted_before.begin(), sorted_before.end()), std::sort(sorted_after.begin(), sorted_after.end());
        CHECK(sorted_before == sorted_after);
        // Both sealed: all of it one-sided, faces included, nothing moved.
        for (sim::VolumeConstraint& v : b.volumes) v.leak = 0.0f;
        std::vector<mesh::Triangle> again = b.triangles;
        const scene::SolidOrder all = scene::order_solids_first(b, scene::solid_pieces(b, nullptr), again, nullptr);
        CHECK(all.all);
        CHECK(all.one_sided(again.size() + 10) == again.size() + 10);
        CHECK(again == b.triangles);
    }
}
