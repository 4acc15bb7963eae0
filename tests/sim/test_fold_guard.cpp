#include <doctest/doctest.h>

#include <cmath>

#include "mesh/procedural.h"
#include "core/thread_pool.h"
#include "sim/crossings.h"
#include "sim/state_hash.h"
#include "sim/sim_fixtures.h"
#include "topology/cut.h"

#include <algorithm>
#include <vector>

using namespace pbdsplat;

namespace {

// A 2 m sheet of 16 x 16 quads (edges 0.125-0.18 m), its half x > 0 folded about the line x = 0
// by `degrees` over the half x < 0 (pinned, at y = 0) and thrown down onto it at 3 m/s. Returns
// how many particles of the fold with rest x in (0.05, `reach`) ended more than 5 mm below the
// pinned half, which is through it, summed over 30 frames.
int folded_through(const sim::ContactSettings& contact, float degrees, float reach) {
    sim::SoftBodyDesc d;
    d.volume = false;
    sim::SoftBody b = test::make_body(mesh::grid_sheet(16, 2.0f), d);
    const float phi = degrees * float(M_PI) / 180.0f;
    for (size_t i = 0; i < b.particle_count(); ++i) {
        const Vec3f r = b.rest_positions[i];
        if (r.x() <= 0.0f) {
            b.pin(uint32_t(i));
            continue;
        }
        const Vec3f p(r.x() * std::cos(phi), r.x() * std::sin(phi), r.z());
        b.particles.x[i] = b.particles.x_prev[i] = sim::to4(p);
        b.particles.v[i] = sim::to4(Vec3f(0.0f, -3.0f, 0.0f));
    }
    sim::SolverSettings s;
    s.gravity = Vec3f::Zero();
    s.iterations = 10;
    s.contact = contact;
    sim::Solver solver;
    int through = 0;
    for (int f = 0; f < 30; ++f) {
        solver.step(b, 1.0f / 60.0f, s, {}, {});
        for (size_t i = 0; i < b.particle_count(); ++i) {
            const Vec3f r = b.rest_positions[i];
            // Not the sheet's side edges, where a particle may come round the pinned half.
            if (r.x() > 0.05f && r.x() < reach && std::abs(r.z()) < 0.8f && b.particles.x[i].y() < -0.005f) ++through;
        }
    }
    return through;
}

// The first ring past the hinge: folded over, it lands about 0.25 m from where it lay, within the
// neighbourhood (2.75 mean edges, 0.39 m) that contact leaves alone.
constexpr float k_first_ring = 0.19f;
// The fold's first four rings, most of them landing beyond that neighbourhood.
constexpr float k_four_rings = 0.6f;

sim::ContactSettings contact(bool folds, bool self) {
    sim::ContactSettings c;
    c.folds = folds, c.self = self;
    return c;
}

// Whether the lists `kept` updated through the edits equal those remade from the whole of `b`.
void check_same_lists(const sim::SoftBody& b, const sim::FoldGuard& kept) {
    sim::FoldGuard fresh = kept;
    fresh.rebuild(b);
    REQUIRE(fresh.pairs() > 0);
    size_t differ = 0;
    for (uint32_t i = 0; i < b.particle_count(); ++i) {
        std::vector<uint32_t> x(kept.neighbourhood(i).begin(), kept.neighbourhood(i).end());
        std::vector<uint32_t> y(fresh.neighbourhood(i).begin(), fresh.neighbourhood(i).end());
        std::sort(x.begin(), x.end()), std::sort(y.begin(), y.end());
        differ += x != y ? 1 : 0;
    }
    CHECK(differ == 0);
    CHECK(kept.pairs() == fresh.pairs());
}

} // namespace

TEST_SUITE("sim/fold_guard") {
    TEST_CASE("a sheet folded onto itself at its hinge stays on its side") {
        CHECK(folded_through(contact(true, false), 170.0f, k_first_ring) == 0);
        CHECK(folded_through(contact(true, false), 150.0f, k_first_ring) == 0);
        // Without the guard the same rings pass through (the checks above can fail), self-contact
        // or not: its neighbourhood is left to the guard.
        CHECK(folded_through(contact(false, false), 170.0f, k_first_ring) > 0);
        CHECK(folded_through(contact(false, true), 170.0f, k_first_ring) > 0);
    }

    TEST_CASE("with self-contact the whole fold holds: the guard near the hinge, contact beyond") {
        CHECK(folded_through(contact(true, true), 170.0f, k_four_rings) == 0);
        // The guard alone leaves the far rings to self-contact.
        CHECK(folded_through(contact(true, false), 170.0f, k_four_rings) > 0);
    }

    TEST_CASE("a body at rest, or bending smoothly, is never pushed") {
        sim::SoftBody b = test::make_body(mesh::icosphere(3, 0.5f));
        sim::SolverSettings s;
        s.gravity = Vec3f::Zero();
        sim::Solver solver;
        // A smooth squeeze: every particle's velocity towards the equator plane, as a ball pressed flat.
        for (size_t i = 0; i < b.particle_count(); ++i) b.particles.v[i] = sim::to4(Vec3f(0.0f, -0.5f * b.particles.x[i].y(), 0.0f));
        const sim::SoftBody before = b;
        solver.step(b, 1.0f / 60.0f, s, {}, {});
        CHECK(solver.folds().pairs() > 0);
        CHECK(solver.folds().candidates() == 0);
        // The same step without the guard's stage lands on the same positions.
        sim::SoftBody other = before;
        sim::Solver plain;
        sim::SolverSettings off = s;
        off.contact.folds = false;
        plain.step(other, 1.0f / 60.0f, off, {}, {});
        for (size_t i = 0; i < b.particle_count(); ++i) CHECK(b.particles.x[i] == other.particles.x[i]);
    }

    TEST_CASE("after a slit and a cut, the lists kept and remade around the edit equal lists made afresh") {
        sim::SoftBody b = test::make_body(mesh::icosphere(3, 0.5f));
        sim::Solver solver;
        const sim::SolverSettings s;
        solver.step(b, 1.0f / 60.0f, s, {}, {});
        topology::CutOptions cut;
        cut.reference_edge_length = float(b.distance_groups.mean_rest());
        const uint32_t top = b.extreme_particle(1, true);
        auto slit = topology::cut(b, topology::local_cut_on(b, top, Vec3f::UnitX(), 1.5f * cut.reference_edge_length), cut);
        REQUIRE(slit.ok());
        REQUIRE(slit.value().changed());
        solver.step(b, 1.0f / 60.0f, s, {}, {});
        check_same_lists(b, solver.folds());
        test::cut_in_two(b, Vec3f(0.0f, -0.1f, 0.0f), Vec3f(0.2f, 1.0f, 0.1f));
        solver.step(b, 1.0f / 60.0f, s, {}, {});
        check_same_lists(b, solver.folds());
    }

    TEST_CASE("determinism: a crumpling ball's folds come out the same for any thread count") {
        auto run_hash = [](unsigned threads, size_t& most) {
            auto b = test::make_body(mesh::icosphere(4, 0.5f));
            b.volumes[0].pressure = 0.3f;  // crushed to 0.3 of its volume: it creases and folds
            sim::SolverSettings s;
            s.gravity = Vec3f::Zero();
            core::ThreadPool pool(threads);
            sim::Solver solver(&pool);
            most = 0;
            for (int f = 0; f < 60; ++f) {
                solver.step(b, 1.0f / 60.0f, s, {}, {});
                most = std::max(most, solver.folds().candidates());
            }
            return sim::state_hash(b.particles);
        };
        size_t most1 = 0, most2 = 0, most3 = 0;
        const uint64_t one = run_hash(1, most1);
        MESSAGE("most candidates in a substep: " << most1);
        CHECK(most1 > 0);  // the guard acts here, so the hashes below test its scan
        CHECK(run_hash(2, most2) == one);
        CHECK(run_hash(3, most3) == one);
        CHECK(most2 == most1);
    }

    TEST_CASE("edges: a crumpling ball's folds cross less with its edges held apart, the same for any thread count") {
        // Crushed to 0.6 of its volume the ball creases and lays folds against each other, where
        // edges slice through edges with no corner over the other's triangles.
        auto crumple = [](bool edges, unsigned threads, size_t& most, double& crossing) {
            auto b = test::make_body(mesh::icosphere(4, 0.5f));
            b.volumes[0].pressure = 0.6f;
            sim::SolverSettings s;
            s.gravity = Vec3f::Zero();
            s.contact.fold_edges = edges;
            core::ThreadPool pool(threads);
            sim::Solver solver(&pool);
            most = 0, crossing = 0.0;
            for (int f = 0; f < 90; ++f) {
                solver.step(b, 1.0f / 60.0f, s, {}, {});
                most = std::max(most, solver.folds().edge_candidates());
                if (f % 10 == 9) crossing = std::max(crossing, sim::surface_crossings(b).ratio);
            }
            return sim::state_hash(b.particles);
        };
        size_t most_off = 0, most_on = 0, most_on2 = 0;
        double off = 0.0, on = 0.0, on2 = 0.0;
        crumple(false, 1, most_off, off);
        const uint64_t one = crumple(true, 1, most_on, on);
        MESSAGE("crossing without / with edges: " << off << " / " << on << ", most edge candidates " << most_on);
        CHECK(most_off == 0);
        CHECK(most_on > 0);
        // Measured 12-04: 0.026 without, 0.0125 with (0.4 of its volume: 0.30 / 0.31, where
        // the folds cross beyond the 1.5 edges the pairs reach); asserted at two thirds.
        CHECK(on < 0.67 * off);
        CHECK(crumple(true, 2, most_on2, on2) == one);
        CHECK(most_on2 == most_on);
    }

    TEST_CASE("edges: the closest points of two lines, and none for parallel ones") {
        // An X of two edges 0.05 apart, crossing at a quarter of the first and the middle of the second.
        float s = 0.0f, t = 0.0f;
        REQUIRE(sim::line_closest_params(Vec3f(-1, 0, 0), Vec3f(3, 0, 0), Vec3f(0, 0.05f, -1), Vec3f(0, 0.05f, 1), 0.2f, s, t));
        CHECK(s == doctest::Approx(0.25f));
        CHECK(t == doctest::Approx(0.5f));
        // Parallel edges have no normal to keep a side along.
        CHECK_FALSE(sim::line_closest_params(Vec3f(0, 0, 0), Vec3f(1, 0, 0), Vec3f(0, 1, 0), Vec3f(2, 1, 0.01f), 0.2f, s, t));
    }

    TEST_CASE("stiff bodies keep no pairs: their pieces do not fold") {
        sim::SoftBodyDesc d;
        d.shape_matching = true;
        sim::SoftBody b = test::make_body(mesh::icosphere(3, 0.5f), d);
        sim::SolverSettings s;
        s.shape_stiffness = 1.0f;
        sim::Solver solver;
        solver.step(b, 1.0f / 60.0f, s, {}, {});
        CHECK(solver.folds().pairs() == 0);
        sim::Solver soft;
        s.shape_stiffness = 0.2f;
        soft.step(b, 1.0f / 60.0f, s, {}, {});
        CHECK(soft.folds().pairs() > 0);
    }
}
