#include <doctest/doctest.h>

#include <algorithm>

#include "mesh/procedural.h"
#include "sim/sim_fixtures.h"
#include "topology/piece_split.h"

using namespace pbdsplat;

namespace {
// Three separate spheres of 162, 642 and 2,562 particles under one piece label: what an edit
// that split a piece in three leaves before the labels are fixed.
sim::SoftBody three_spheres_as_one_piece() {
    mesh::TriangleMesh m;
    const uint32_t levels[3] = {2, 3, 4};
    for (int k = 0; k < 3; ++k) {
        const mesh::TriangleMesh s = mesh::icosphere(levels[k], 0.5f + 0.25f * float(k));
        const uint32_t first = uint32_t(m.positions.size());
        for (const Vec3f& p : s.positions) m.positions.push_back(p + Vec3f(3.0f * float(k), 0.0f, 0.0f));
        for (const mesh::Triangle& t : s.triangles) m.triangles.push_back({t[0] + first, t[1] + first, t[2] + first});
    }
    sim::SoftBody b = test::make_body(std::move(m));
    std::fill(b.piece_of_particle.begin(), b.piece_of_particle.end(), 0u);
    b.pieces = 1;
    return b;
}

// One seed on each sphere (the particle nearest its centre's +y pole), ascending.
std::vector<uint32_t> a_seed_per_sphere(const sim::SoftBody& b) {
    std::vector<uint32_t> seeds;
    for (int k = 0; k < 3; ++k) {
        uint32_t best = 0;
        float best_d = 1e30f;
        for (uint32_t v = 0; v < b.particle_count(); ++v) {
            const float d = (b.particles.x[v].head<3>() - Vec3f(3.0f * float(k), 2.0f, 0.0f)).squaredNorm();
            if (d < best_d) best_d = d, best = v;
        }
        seeds.push_back(best);
    }
    std::sort(seeds.begin(), seeds.end());
    return seeds;
}

std::vector<uint32_t> sorted(std::vector<uint32_t> v) {
    std::sort(v.begin(), v.end());
    return v;
}
} // namespace

TEST_SUITE("topology/piece_split") {
    TEST_CASE("the sweep past the budget finds the parts and sums the breadth-first search finds") {
        sim::SoftBody searched = three_spheres_as_one_piece();
        sim::SoftBody swept = searched;
        const std::vector<uint32_t> seeds = a_seed_per_sphere(searched);
        const uint32_t reached[1] = {0};
        const uint8_t measured[1] = {0};
        // A budget past the body: the search runs until all but the largest sphere have closed.
        const topology::SplitSearch a = topology::split_pieces(searched, reached, measured, seeds, 1u << 30);
        // No budget: the piece is swept at once.
        const topology::SplitSearch b = topology::split_pieces(swept, reached, measured, seeds, 0);
        CHECK(a.searched_whole == 0);
        CHECK(b.searched_whole == 1);
        CHECK(b.searched >= swept.particle_count());
        REQUIRE(a.parts_of.size() == 1);
        REQUIRE(b.parts_of.size() == 1);
        const std::vector<topology::Part>& pa = a.parts_of[0];
        const std::vector<topology::Part>& pb = b.parts_of[0];
        REQUIRE(pa.size() == 3);
        REQUIRE(pb.size() == 3);
        // The rest (the largest sphere) keeps the label, unsummed; the two cut off are complete.
        CHECK_FALSE(pa[0].complete);
        CHECK_FALSE(pb[0].complete);
        CHECK(pb[0].label == 0);
        for (size_t k = 1; k < 3; ++k) {
            CHECK(pa[k].complete);
            CHECK(pb[k].complete);
            CHECK(pa[k].label == pb[k].label);
            CHECK(sorted(pa[k].particles) == sorted(pb[k].particles));
            CHECK(pa[k].triangles == pb[k].triangles);
            CHECK(pb[k].six_v == doctest::Approx(pa[k].six_v).epsilon(1e-5));
            CHECK(pb[k].area_bound == doctest::Approx(pa[k].area_bound).epsilon(1e-5));
            CHECK(pb[k].six_v > 0.0);
        }
        CHECK(pb[1].particles.size() == 642);
        CHECK(pb[2].particles.size() == 162);
        CHECK(pb[1].triangles == 1280);
        CHECK(pb[2].triangles == 320);
        // Both relabel alike: three pieces, each sphere one label.
        CHECK(searched.piece_of_particle == swept.piece_of_particle);
        CHECK(swept.pieces == 3);
    }

    TEST_CASE("with sides, the searches flood the smaller side's parts one at a time and find what the search finds") {
        sim::SoftBody searched = three_spheres_as_one_piece();
        sim::SoftBody flooded = searched;
        const std::vector<uint32_t> seeds = a_seed_per_sphere(searched);
        const uint32_t reached[1] = {0};
        const uint8_t measured[1] = {0};
        // The two small spheres (804 particles) on the negative side, the large one (2,562) on
        // the positive: the floods take the small ones and never enter the large one past the
        // first rings.
        std::vector<int8_t> side(flooded.particle_count());
        for (uint32_t v = 0; v < side.size(); ++v) side[v] = flooded.particles.x[v].x() < 4.5f ? int8_t(-1) : int8_t(1);
        const topology::SplitSearch a = topology::split_pieces(searched, reached, measured, seeds, 1u << 30);
        const topology::SplitSearch f = topology::split_pieces(flooded, reached, measured, seeds, 1u << 30, side);
        CHECK(f.searched_whole == 0);
        CHECK(f.searched < 804 + 300);
        CHECK(f.searched < a.searched);
        REQUIRE(f.parts_of[0].size() == 3);
        CHECK_FALSE(f.parts_of[0][0].complete);
        for (size_t k = 1; k < 3; ++k) {
            const topology::Part& pa = a.parts_of[0][k];
            const topology::Part& pf = f.parts_of[0][k];
            CHECK(pf.complete);
            CHECK(pf.label == pa.label);
            CHECK(sorted(pf.particles) == sorted(pa.particles));
            CHECK(pf.triangles == pa.triangles);
            CHECK(pf.six_v == doctest::Approx(pa.six_v).epsilon(1e-5));
            CHECK(pf.area_bound == doctest::Approx(pa.area_bound).epsilon(1e-5));
        }
        CHECK(searched.piece_of_particle == flooded.piece_of_particle);
        CHECK(flooded.pieces == 3);
    }

    TEST_CASE("a flood that meets the search from the other side falls back to the sweep and leaves the piece whole") {
        // One sphere seeded at both poles, the sides split at the equator as a cut that did not
        // go through would leave them: the searches meet past the first rings.
        sim::SoftBody b = test::make_body(mesh::icosphere(3));
        const uint32_t reached[1] = {0};
        const uint8_t measured[1] = {0};
        const std::vector<uint32_t> seeds = sorted({b.extreme_particle(1), b.extreme_particle(1, false)});
        std::vector<int8_t> side(b.particle_count());
        for (uint32_t v = 0; v < side.size(); ++v) side[v] = b.particles.x[v].y() < 0.0f ? int8_t(-1) : int8_t(1);
        const topology::SplitSearch s = topology::split_pieces(b, reached, measured, seeds, 1u << 30, side);
        CHECK(s.searched_whole == 1);
        REQUIRE(s.parts_of[0].size() == 1);
        CHECK_FALSE(s.parts_of[0][0].complete);
        CHECK(b.pieces == 1);
        CHECK(std::all_of(b.piece_of_particle.begin(), b.piece_of_particle.end(), [](uint32_t p) { return p == 0; }));
    }

    TEST_CASE("a sweep of a piece with no solver measure sums its rest too") {
        sim::SoftBody b = three_spheres_as_one_piece();
        const std::vector<uint32_t> seeds = a_seed_per_sphere(b);
        const uint32_t reached[1] = {0};
        const uint8_t unmeasured[1] = {1};
        const topology::SplitSearch s = topology::split_pieces(b, reached, unmeasured, seeds, 0);
        REQUIRE(s.parts_of[0].size() == 3);
        const topology::Part& rest = s.parts_of[0][0];
        CHECK(rest.complete);
        CHECK(rest.label == 0);
        CHECK(rest.particles.size() == 2562);
        CHECK(rest.triangles == 5120);
        // 6V of a sphere of radius 1 (the inscribed polyhedron a little less).
        CHECK(rest.six_v / 6.0 == doctest::Approx(4.0 / 3.0 * 3.14159265).epsilon(0.01));
        CHECK(std::all_of(rest.particles.begin(), rest.particles.end(), [&](uint32_t v) { return b.piece_of_particle[v] == 0; }));
    }

    TEST_CASE("a sweep of a piece that did not fall apart leaves it whole") {
        sim::SoftBody b = test::make_body(mesh::icosphere(3));
        const uint32_t reached[1] = {0};
        const uint8_t measured[1] = {0};
        const std::vector<uint32_t> seeds = {0, b.extreme_particle(0), b.extreme_particle(1, false)};
        const topology::SplitSearch s = topology::split_pieces(b, reached, measured, sorted(seeds), 0);
        REQUIRE(s.parts_of[0].size() == 1);
        CHECK_FALSE(s.parts_of[0][0].complete);
        CHECK(b.pieces == 1);
        CHECK(std::all_of(b.piece_of_particle.begin(), b.piece_of_particle.end(), [](uint32_t p) { return p == 0; }));
    }
}
