#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "mesh/procedural.h"
#include "sim/sim_fixtures.h"
#include "sim/sleep.h"
#include "sim/solver.h"

using namespace pbdsplat;

namespace {

sim::SoftBody boxes(std::initializer_list<Vec3f> centres) {
    mesh::TriangleMesh m;
    for (const Vec3f& c : centres) mesh::append(m, mesh::box(Vec3f(0.5f, 0.3f, 0.5f), 2), test::moved_by(c));
    sim::SoftBodyDesc d;
    d.shape_matching = true;
    sim::SoftBody b = test::make_body(std::move(m), d);
    b.model_of_particle = b.piece_of_particle;  // separate models, as [[bodies]] are
    return b;
}

sim::SolverSettings stiff() {
    sim::SolverSettings s;
    s.iterations = 10;
    s.shape_stiffness = 0.8f;
    s.damping = 0.5f;
    return s;
}

sim::Colliders ground() {
    sim::Colliders c;
    c.ground = sim::GroundPlane{Vec3f::UnitY(), 0.0f};
    return c;
}

bool piece_held(const sim::SoftBody& b, uint32_t piece) {
    for (size_t i = 0; i < b.particle_count(); ++i)
        if (b.piece_of_particle[i] == piece && b.particles.w[i] > 0.0f) return false;
    return true;
}

// Two boxes stacked (boxes() at y 0.16 and 0.47), the upper moved by hand for the first second
// (awake, its particles' speeds left at 0): the frames of two seconds of update_sleep at which
// the lower and the upper first fall asleep (-1: never).
std::pair<int, int> asleep_frames(sim::SoftBody& b, std::span<const std::pair<uint32_t, uint32_t>> touching = {},
                                  std::span<const uint8_t> gives = {}) {
    const uint32_t low = b.piece_of_particle[b.extreme_particle(1, false)], high = 1 - low;
    const sim::SleepSettings s;
    int low_asleep_at = -1, high_asleep_at = -1;
    for (int f = 0; f < 120; ++f) {
        if (f < 60)
            for (size_t i = 0; i < b.particle_count(); ++i)
                if (b.piece_of_particle[i] == high) b.particles.x[i] += sim::to4(Vec3f(0.02f, 0.0f, 0.0f));
        sim::update_sleep(b, touching, s, 1.0f / 60.0f, gives);
        if (low_asleep_at < 0 && piece_held(b, low)) low_asleep_at = f;
        if (high_asleep_at < 0 && piece_held(b, high)) high_asleep_at = f;
    }
    return {low_asleep_at, high_asleep_at};
}

} // namespace

TEST_SUITE("sim/sleep") {
    TEST_CASE("a stack that landed falls asleep, holds still to the bit, and searches no more") {
        sim::SoftBody b = boxes({{0.0f, 0.2f, 0.0f}, {0.02f, 0.55f, 0.0f}});
        const std::vector<float> masses = b.particles.w;
        sim::Solver solver;
        const sim::SolverSettings s = stiff();
        const sim::Colliders c = ground();
        for (int f = 0; f < 180; ++f) solver.step(b, 1.0f / 60.0f, s, c, {});
        MESSAGE("asleep after 3 s: " << b.sleep.sleeping << " of " << b.pieces);
        REQUIRE(b.sleep.sleeping == 2);
        CHECK(piece_held(b, 0));
        CHECK(piece_held(b, 1));
        CHECK(b.sleep.resting());  // the frame's stages then have nothing to do
        const sim::Vec4Array x = b.particles.x;
        const size_t searches = solver.contact().searches();
        for (int f = 0; f < 60; ++f) solver.step(b, 1.0f / 60.0f, s, c, {});
        CHECK(b.particles.x == x);
        CHECK(solver.contact().searches() == searches);
        // Woken, every particle has its own mass back, exactly.
        sim::wake_all(b);
        CHECK(b.particles.w == masses);
        CHECK(b.sleep.sleeping == 0);
    }

    TEST_CASE("without sleep the same stack keeps moving (the test above can fail)") {
        sim::SoftBody b = boxes({{0.0f, 0.2f, 0.0f}, {0.02f, 0.55f, 0.0f}});
        sim::SolverSettings s = stiff();
        s.sleep.enabled = false;
        sim::Solver solver;
        for (int f = 0; f < 180; ++f) solver.step(b, 1.0f / 60.0f, s, ground(), {});
        const sim::Vec4Array x = b.particles.x;
        solver.step(b, 1.0f / 60.0f, s, ground(), {});
        CHECK(b.sleep.sleeping == 0);
        CHECK(b.particles.x != x);
    }

    TEST_CASE("a box dropped onto a sleeping one wakes it, and rests on it") {
        // The lower box sleeps within a second; the upper one falls 3 m (0.8 s) onto it.
        sim::SoftBody b = boxes({{0.0f, 0.16f, 0.0f}, {0.05f, 3.5f, 0.0f}});
        const uint32_t low = b.piece_of_particle[b.extreme_particle(1, false)];
        const uint32_t high = 1 - low;
        sim::Solver solver;
        const sim::SolverSettings s = stiff();
        bool slept = false, woke = false;
        for (int f = 0; f < 240; ++f) {
            solver.step(b, 1.0f / 60.0f, s, ground(), {});
            const bool held = piece_held(b, low);
            slept = slept || held;
            woke = woke || (slept && !held);
        }
        MESSAGE("the lower box slept: " << slept << ", woke: " << woke);
        CHECK(slept);
        CHECK(woke);
        CHECK(test::lowest_y(b, high) > test::highest_y(b, low) - 0.05f);  // on it, not through it
        CHECK(test::highest_y(b, low) > 0.28f);  // and the lower box not crushed into the ground
    }

    TEST_CASE("wake_pieces frees the named pieces alone, each particle with its own mass") {
        sim::SoftBody b = boxes({{0.0f, 0.2f, 0.0f}, {0.02f, 0.55f, 0.0f}});
        const std::vector<float> masses = b.particles.w;
        sim::Solver solver;
        for (int f = 0; f < 180; ++f) solver.step(b, 1.0f / 60.0f, stiff(), ground(), {});
        REQUIRE(b.sleep.sleeping == 2);
        const uint32_t top = b.piece_of_particle[b.extreme_particle(1, true)];
        const uint32_t named[] = {top};
        sim::wake_pieces(b, std::span<const uint32_t>(named));
        CHECK(b.sleep.sleeping == 1);
        CHECK_FALSE(b.sleep.resting());
        CHECK(piece_held(b, 1 - top));
        for (size_t i = 0; i < b.particle_count(); ++i)
            if (b.piece_of_particle[i] == top) REQUIRE(b.particles.w[i] == masses[i]);
    }

    TEST_CASE("a sleeping piece struck hard gives within the frame, and the striker is not flung back") {
        // Held through the frame of the blow (woken only at its end, as before), the lower box
        // took nothing: the upper one alone answered the contact against its own constraints.
        // In a heap that flung small pieces off at up to 50 m/s (docs/BENCHMARKS.md, "Contact").
        sim::SoftBody b = boxes({{0.0f, 0.2f, 0.0f}, {0.02f, 0.55f, 0.0f}});
        sim::Solver solver;
        const sim::SolverSettings s = stiff();
        for (int f = 0; f < 180; ++f) solver.step(b, 1.0f / 60.0f, s, ground(), {});
        REQUIRE(b.sleep.sleeping == 2);
        const uint32_t top = b.piece_of_particle[b.extreme_particle(1, true)], low = 1 - top;
        const uint32_t named[] = {top};
        sim::wake_pieces(b, std::span<const uint32_t>(named));
        const float speed = 30.0f;  // a substep closes 12.5 cm, twice the thickness
        for (size_t i = 0; i < b.particle_count(); ++i)
            if (b.piece_of_particle[i] == top) b.particles.v[i] = sim::to4(Vec3f(0.0f, -speed, 0.0f));
        const sim::Vec4Array before = b.particles.x;
        solver.step(b, 1.0f / 60.0f, s, ground(), {});
        float moved = 0.0f;
        for (size_t i = 0; i < b.particle_count(); ++i)
            if (b.piece_of_particle[i] == low) moved = std::max(moved, float((b.particles.x[i] - before[i]).norm()));
        MESSAGE("the struck box moved " << moved << " m in the frame of the blow");
        CHECK(moved > 1e-3f);  // measured: 0.044 m; held through the frame, it moved 0
        float fastest = 0.0f;
        for (int f = 0; f < 30; ++f) {
            solver.step(b, 1.0f / 60.0f, s, ground(), {});
            for (size_t i = 0; i < b.particle_count(); ++i) fastest = std::max(fastest, float(b.particles.v[i].norm()));
        }
        MESSAGE("fastest particle after the blow: " << fastest << " m/s");
        CHECK(fastest < speed);  // measured: 11.5 m/s (the pair pressed into the ground), no faster than the blow
        CHECK(test::lowest_y(b, top) > test::highest_y(b, low) - 0.05f);  // on it, not through it
    }

    TEST_CASE("a piece that keeps moving never sleeps; one at rest beside it does") {
        // A box on the ground and a second one sliding across it at 1 m/s: the slider never
        // stays within the still radius, so it never sleeps.
        sim::SoftBody b = boxes({{0.0f, 0.16f, 0.0f}, {-2.0f, 0.16f, 1.5f}});
        const uint32_t slider = b.piece_of_particle[b.extreme_particle(0, false)];
        sim::SolverSettings s = stiff();
        s.gravity = Vec3f::Zero();
        sim::Solver solver;
        for (size_t i = 0; i < b.particle_count(); ++i)
            if (b.piece_of_particle[i] == slider) b.particles.v[i] = sim::to4(Vec3f(1.0f, 0.0f, 0.0f));
        for (int f = 0; f < 120; ++f) {
            solver.step(b, 1.0f / 60.0f, s, {}, {});
            REQUIRE(!piece_held(b, slider));
        }
        CHECK(b.sleep.sleeping == 1);  // the box at rest
    }

    TEST_CASE("welded pieces sleep and wake as one") {
        // Two boxes, one still and one moved by hand, a weld between them (a table's leg and its
        // top). Asleep, the still one would hold its end of the weld while the other pulls: a
        // table of welded parts flew apart at 100 m/s within a second of its legs falling asleep.
        auto run = [](bool welded) {
            sim::SoftBody b = boxes({{0.0f, 0.16f, 0.0f}, {0.0f, 0.47f, 0.0f}});
            if (welded) {
                const uint32_t i = b.extreme_particle(1, false), j = b.extreme_particle(1, true);
                b.welds.push_back({i, j, float((b.particles.x[i] - b.particles.x[j]).norm()), 0.0f});
            }
            const auto [low_asleep_at, high_asleep_at] = asleep_frames(b);
            MESSAGE(std::string(welded ? "welded" : "apart") << ": the still box asleep at frame " << low_asleep_at << ", the moved one at "
                                                  << high_asleep_at);
            return std::make_pair(std::make_pair(low_asleep_at, high_asleep_at), b);
        };
        const auto [apart, apart_body] = run(false);
        CHECK(apart.first >= 0);
        CHECK(apart.first < 60);  // alone, the still box sleeps while the other moves
        auto [welded, b] = run(true);
        CHECK(welded.first >= 60);  // welded to a moving box, it waits for it
        CHECK(welded.first == welded.second);  // and they fall asleep together
        REQUIRE(b.sleep.sleeping == 2);
        const uint32_t low = b.piece_of_particle[b.extreme_particle(1, false)];
        const uint32_t named[] = {low};
        sim::wake_pieces(b, std::span<const uint32_t>(named));
        CHECK(b.sleep.sleeping == 0);  // waking one wakes the piece welded to it
        CHECK_FALSE(piece_held(b, 1 - low));
    }

    TEST_CASE("a piece that gives under contact falls asleep only with the awake pieces it touches") {
        // A still box touching one moved by hand for a second. A stiff box sleeps while the other
        // moves; one that gives (a soft body, answered particle by particle) waits for it: held
        // under a ball pressed into its dent, it flung the ball 1.5 m/s up each time it fell asleep.
        auto run = [](uint8_t gives) {
            sim::SoftBody b = boxes({{0.0f, 0.16f, 0.0f}, {0.0f, 0.47f, 0.0f}});
            const uint32_t low = b.piece_of_particle[b.extreme_particle(1, false)];
            const std::pair<uint32_t, uint32_t> touching[] = {{0u, 1u}};
            std::vector<uint8_t> giving(2, 0);
            giving[low] = gives;
            const auto [low_asleep_at, high_asleep_at] = asleep_frames(b, touching, giving);
            MESSAGE(std::string(gives ? "giving" : "stiff") << ": the still box asleep at frame " << low_asleep_at << ", the moved one at "
                                                  << high_asleep_at);
            return std::make_pair(low_asleep_at, high_asleep_at);
        };
        const auto stiff_box = run(0);
        CHECK(stiff_box.first >= 0);
        CHECK(stiff_box.first < 60);  // it sleeps while the other moves
        const auto giving = run(1);
        CHECK(giving.first >= 60);               // it waits for the moved one
        CHECK(giving.first == giving.second);  // and they fall asleep together
    }

    TEST_CASE("a static body alone rests from its first frame: nothing can move, so nothing is computed") {
        // A table with nothing on it: every particle pinned. It used to run every stage of every
        // frame (a pinned icosphere: 1.6 ms a frame for nothing).
        sim::SoftBody b = boxes({{0.0f, 0.16f, 0.0f}});
        for (uint32_t i = 0; i < uint32_t(b.particle_count()); ++i) b.pin(i);
        sim::Solver solver;
        const sim::SolverSettings s = stiff();
        CHECK_FALSE(b.sleep.resting());  // not judged yet
        solver.step(b, 1.0f / 60.0f, s, ground(), {});
        CHECK(b.sleep.movable == 0);
        CHECK(b.sleep.resting());
        const sim::Vec4Array x = b.particles.x;
        for (int f = 0; f < 10; ++f) solver.step(b, 1.0f / 60.0f, s, ground(), {});
        CHECK(b.particles.x == x);
        // Woken (as a cut or a drag wakes it), it is judged again before it rests.
        sim::wake_all(b);
        CHECK_FALSE(b.sleep.resting());
        solver.step(b, 1.0f / 60.0f, s, ground(), {});
        CHECK(b.sleep.resting());
        // One free piece beside it keeps the frame at work.
        sim::SoftBody two = boxes({{0.0f, 0.16f, 0.0f}, {2.0f, 0.5f, 0.0f}});
        for (uint32_t i = 0; i < uint32_t(two.particle_count()); ++i)
            if (two.piece_of_particle[i] == two.piece_of_particle[0]) two.pin(i);
        solver.step(two, 1.0f / 60.0f, s, ground(), {});
        CHECK(two.sleep.movable == 1);
        CHECK_FALSE(two.sleep.resting());
    }
}
