#include <doctest/doctest.h>

#include <algorithm>

#include "mesh/procedural.h"
#include "sim/pose.h"
#include "sim/solver.h"
#include "topology/invariants.h"
#include "topology/tear.h"
#include "support/why.h"

using namespace pbdsplat;

namespace {
sim::SoftBody sheet() {
    auto b = sim::make_soft_body(mesh::grid_sheet(20, 2.0f), {.volume = false});
    REQUIRE(b.ok());
    return std::move(b).value();
}
} // namespace

TEST_SUITE("topology/tear") {
    TEST_CASE("nothing tears below the threshold") {
        sim::SoftBody b = sheet();
        const size_t n = b.particle_count();
        auto t = topology::tear_once(b, {}, {});
        REQUIRE(t.ok());
        CHECK_FALSE(t.value().has_value());
        CHECK(b.particle_count() == n);
    }

    TEST_CASE("a sheet pulled at one point tears a piece off, a few edges per frame, keeping every invariant") {
        sim::SoftBody b = sheet();
        const float edge = 2.0f / 20.0f;
        // Hang the sheet by its near row and pull the middle of the far row away.
        uint32_t grab = 0;
        for (uint32_t i = 0; i < b.particle_count(); ++i) {
            const Vec3f x = sim::xyz(b.particles.x[i]);
            if (x.z() < -0.99f) b.pin(i);
            if (x.z() > 0.99f && std::abs(x.x()) < std::abs(sim::xyz(b.particles.x[grab]).x()) + 1e-6f) grab = i;
        }
        REQUIRE(b.particles.x[grab].z() > 0.99f);
        b.pin(grab);
        sim::Solver solver;
        sim::SolverSettings s;
        s.gravity = Vec3f::Zero();
        s.volume = false;
        topology::TearOptions tear;
        tear.threshold = 1.6f;
        tear.max_per_frame = 2;
        topology::CutOptions cut;
        cut.reference_edge_length = edge;
        size_t torn = 0, most_in_a_frame = 0, tearing_frames = 0;
        for (int frame = 0; frame < 180; ++frame) {
            b.particles.x[grab].z() += 1.5f / 60.0f;  // pulled away at 1.5 units a second
            size_t this_frame = 0;
            for (uint32_t k = 0; k < tear.max_per_frame; ++k) {
                auto t = topology::tear_once(b, tear, cut);
                REQUIRE_MESSAGE(t.ok(), test::why(t));
                if (!t.value()) break;
                ++this_frame;
                const core::Status st = topology::check_invariants(b);
                REQUIRE_MESSAGE(st.ok(), "frame " << frame << ": " << test::why(st));
            }
            torn += this_frame;
            tearing_frames += this_frame > 0 ? 1 : 0;
            most_in_a_frame = std::max(most_in_a_frame, this_frame);
            solver.step(b, 1.0f / 60.0f, s, {}, {});
            REQUIRE(std::all_of(b.particles.x.begin(), b.particles.x.end(), [](const Vec4f& x) { return x.allFinite(); }));
            if (topology::count_components_and_loops(b).components >= 2) break;
        }
        // Over several frames, a few edges each (3 tears over 2 frames measured: a tear that would
        // cut off a fleck of under 8 triangles waits, so the piece comes off whole).
        CHECK(torn >= 3);
        CHECK(tearing_frames >= 2);
        CHECK(most_in_a_frame <= tear.max_per_frame);
        // The piece around the grabbed point came off; the sheet did not shatter.
        const auto counts = topology::count_components_and_loops(b);
        CHECK(counts.components >= 2);
        CHECK(counts.components <= 4);
        CHECK(sim::smallest_piece_triangles(b) >= tear.min_fragment_triangles);  // no fleck came off
    }

    TEST_CASE("the frame's strained set, kept through tears, equals a fresh scan after each") {
        // A sphere shaken out of shape: many edges past the threshold, tears all over it.
        auto made = sim::make_soft_body(mesh::icosphere(3), {});
        REQUIRE(made.ok());
        sim::SoftBody b = std::move(made).value();
        uint64_t state = 12345;
        auto unit = [&] {
            state = state * 6364136223846793005ull + 1442695040888963407ull;
            return float(state >> 40) / float(1u << 24) - 0.5f;
        };
        const float edge = float(b.distance_groups.mean_rest());
        for (Vec4f& x : b.particles.x) x += Vec4f(unit(), unit(), unit(), 0.0f) * (0.8f * edge);
        topology::TearOptions tear;
        tear.threshold = 1.3f;
        topology::CutOptions cut;
        cut.reference_edge_length = edge;
        topology::StrainedSet strained(b, tear.threshold);
        REQUIRE(strained.size() > 40);
        size_t torn = 0;
        for (int k = 0; k < 40; ++k) {
            auto t = topology::tear_once(b, tear, cut, strained);
            REQUIRE_MESSAGE(t.ok(), test::why(t));
            if (!t.value()) break;
            ++torn;
            const topology::StrainedSet fresh(b, tear.threshold);
            const auto kept = strained.most_strained(SIZE_MAX), scanned = fresh.most_strained(SIZE_MAX);
            REQUIRE(kept.size() == scanned.size());
            for (size_t e = 0; e < kept.size(); ++e) {
                CHECK(kept[e].i == scanned[e].i);
                CHECK(kept[e].j == scanned[e].j);
                CHECK(kept[e].ratio == scanned[e].ratio);
            }
            const core::Status st = topology::check_invariants(b);
            REQUIRE_MESSAGE(st.ok(), test::why(st));
        }
        CHECK(torn >= 20);
    }

    TEST_CASE("tear options are checked") {
        topology::TearOptions o;
        o.threshold = 0.9f;
        CHECK_FALSE(topology::validate(o).ok());
        o = {};
        o.max_per_frame = 0;
        CHECK_FALSE(topology::validate(o).ok());
        CHECK(topology::validate(topology::TearOptions{}).ok());
    }
}
