#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include <limits>
#include <random>

#include "asset/mesh_spec.h"
#include "asset/model_path.h"
#include "mesh/procedural.h"
#include "sim/pose.h"
#include "sim/sim_fixtures.h"
#include "sim/solver.h"
#include "sim/state_hash.h"
#include "sim/weld.h"
#include "topology/cut.h"
#include "topology/invariants.h"

#include "support/skip.h"
#include "support/why.h"
using namespace pbdsplat;

namespace {
using test::total_mass;
double total_volume(const sim::SoftBody& b) {
    double v = 0.0;
    for (size_t k = 0; k < b.volumes.size(); ++k) v += b.volume(k);
    return v;
}
double total_rest_volume(const sim::SoftBody& b) {
    double v = 0.0;
    for (const auto& c : b.volumes) v += c.rest_volume;
    return v;
}
// Largest current / rest ratio over the distance constraints.
float max_strain(const sim::SoftBody& b) {
    float s = 0.0f;
    for (const auto& c : b.distance) s = std::max(s, (b.particles.x[c.i] - b.particles.x[c.j]).head<3>().norm() / c.rest);
    return s;
}
topology::CutSurface plane(const Vec3f& p, const Vec3f& n) {
    auto s = topology::plane_cut(p, n);
    REQUIRE(s.ok());
    return s.value();
}
void require_invariants(const sim::SoftBody& b) {
    const core::Status st = topology::check_invariants(b);
    REQUIRE_MESSAGE(st.ok(), test::why(st));
}
} // namespace

TEST_SUITE("topology/cut") {
    TEST_CASE("a cut severs the welds it passes between, and welded parts it parts match as two objects") {
        // A sheet welded onto a box's top (a lid on a pot), one shape cluster; a vertical plane
        // through both leaves each half of the box with its half of the sheet.
        mesh::TriangleMesh m = mesh::box(Vec3f(1, 1, 1), 4);
        mesh::append(m, mesh::grid_sheet(4, 0.5f), Eigen::Affine3f(Eigen::Translation3f(0.0f, 0.5f, 0.0f)));
        sim::SoftBodyDesc d;
        d.shape_matching = true;
        sim::SoftBody b = test::make_body(std::move(m), d);
        const size_t welds = sim::weld_touching_parts(b, sim::mean_rest_edge_of_models(b));
        REQUIRE(welds > 0);
        sim::rebuild_shape_clusters(b);
        REQUIRE(b.shapes.size() == 1);
        const topology::CutSurface s = plane(Vec3f(0.07f, 0.0f, 0.0f), Vec3f(1.0f, 0.0f, 0.1f));
        auto change = topology::cut(b, s);
        REQUIRE_MESSAGE(change.ok(), test::why(change));
        require_invariants(b);
        CHECK(b.welds.size() < welds);
        for (const sim::DistanceConstraint& w : b.welds) {
            const float di = s.distance(b.particles.x[w.i].head<3>()), dj = s.distance(b.particles.x[w.j].head<3>());
            CHECK(di * dj >= 0.0f);
        }
        CHECK(b.pieces == 4);
        CHECK(b.shapes.size() == 2);
    }

    TEST_CASE("a listed cut (a tear's slit) leaves welds alone") {
        // The same plane as above, as a cut limited to a list of particles (every one): what a
        // tear opens runs through the skin beside a weld and leaves the weld.
        mesh::TriangleMesh m = mesh::box(Vec3f(1, 1, 1), 4);
        mesh::append(m, mesh::grid_sheet(4, 0.5f), Eigen::Affine3f(Eigen::Translation3f(0.0f, 0.5f, 0.0f)));
        sim::SoftBody b = test::make_body(std::move(m));
        const size_t welds = sim::weld_touching_parts(b, sim::mean_rest_edge_of_models(b));
        REQUIRE(welds > 0);
        topology::CutSurface s = plane(Vec3f(0.07f, 0.0f, 0.0f), Vec3f(1.0f, 0.0f, 0.1f));
        for (uint32_t i = 0; i < b.particle_count(); ++i) s.particles.push_back(i);
        auto change = topology::cut(b, s);
        REQUIRE_MESSAGE(change.ok(), test::why(change));
        CHECK(b.pieces == 4);
        CHECK(b.welds.size() == welds);
    }

    TEST_CASE("a plane cuts an icosphere in two capped halves whose volumes sum to the original") {
        sim::SoftBody b = test::make_body(mesh::icosphere(3));
        const double volume = total_volume(b), mass = total_mass(b);
        const size_t n = b.particle_count();
        // Off-centre and tilted, so it crosses edges rather than following them.
        auto change = topology::cut(b, plane(Vec3f(0.05f, 0.02f, 0.0f), Vec3f(1.0f, 0.3f, 0.2f)));
        REQUIRE(change.ok());
        require_invariants(b);
        CHECK(change->components_before == 1);
        CHECK(change->components_after == 2);
        CHECK(change->crossed_edges > 20);
        CHECK(change->duplicated_vertices >= change->crossed_edges);  // every point on a closed cut line splits
        CHECK(b.particle_count() == n + change->new_particles());
        CHECK(change->min_child_area_ratio >= 0.1f * 0.1f * 0.5f);  // snapping keeps slivers out
        CHECK(total_mass(b) == doctest::Approx(mass).epsilon(1e-5));
        const auto counts = topology::count_components_and_loops(b);
        CHECK(counts.components == 2);
        CHECK(counts.boundary_loops == 2);
        REQUIRE(b.volumes.size() == 2);
        for (const auto& v : b.volumes) CHECK(v.cap_loops.size() == 1);
        CHECK(total_volume(b) == doctest::Approx(volume).epsilon(0.01));
        CHECK(total_rest_volume(b) == doctest::Approx(b.volumes.size() == 2 ? volume : 0.0).epsilon(0.01));
        // Nothing moved and no edge got a sudden rest length: the strain is what it was (1).
        CHECK(max_strain(b) == doctest::Approx(1.0f).epsilon(1e-3));
        // The halves keep their volume while they fall apart.
        sim::Solver solver;
        sim::SolverSettings s;
        for (int f = 0; f < 90; ++f) solver.step(b, 1.0f / 60.0f, s, {}, {});
        REQUIRE(std::all_of(b.particles.x.begin(), b.particles.x.end(), [](const Vec4f& x) { return x.allFinite(); }));
        CHECK(total_volume(b) == doctest::Approx(volume).epsilon(0.01));
        require_invariants(b);
    }

    TEST_CASE("the volume policies: burst releases the pressure, rebase keeps the volume of the moment") {
        for (topology::VolumePolicy policy : {topology::VolumePolicy::burst, topology::VolumePolicy::rebase}) {
            sim::SoftBody b = test::make_body(mesh::icosphere(3));
            // Squash the body first so its volume differs from the rest volume.
            for (auto& x : b.particles.x) x.y() *= 0.8f;
            const double squashed = total_volume(b);
            topology::CutOptions o;
            o.volume = policy;
            auto change = topology::cut(b, plane(Vec3f(0.1f, 0.0f, 0.0f), Vec3f(1.0f, 0.1f, 0.0f)), o);
            REQUIRE(change.ok());
            require_invariants(b);
            if (policy == topology::VolumePolicy::burst) {
                // Opened pieces leak: a cut across the ball opens them wide, so their gas escapes at
                // the full rate and within 2 s they are empty.
                REQUIRE(b.volumes.size() == 2);
                for (const auto& v : b.volumes) CHECK(v.leak == doctest::Approx(o.burst_leak));
                sim::Solver solver;
                for (auto& v : b.volumes) v.pressure = 2.0f;
                for (int f = 0; f < 120; ++f) solver.step(b, 1.0f / 60.0f, {}, {}, {});
                for (const auto& v : b.volumes) CHECK(v.leaking_done());
            } else {
                REQUIRE(b.volumes.size() == 2);
                CHECK(total_rest_volume(b) == doctest::Approx(squashed).epsilon(1e-4));
            }
        }
    }

    TEST_CASE("a cut exactly through vertices and along existing edges duplicates them without new particles") {
        // The sheet's vertices at x = 0 form a column of its edges; the box's form a ring.
        sim::SoftBody sheet = test::make_body(mesh::grid_sheet(8, 2.0f), {.volume = false});
        auto change = topology::cut(sheet, plane(Vec3f::Zero(), Vec3f::UnitX()));
        REQUIRE(change.ok());
        require_invariants(sheet);
        CHECK(change->crossed_edges == 0);
        CHECK(change->duplicated_vertices == 9);  // the whole column, its two boundary ends included
        CHECK(change->components_after == 2);

        sim::SoftBody box = test::make_body(mesh::box(Vec3f(1.0f, 1.0f, 1.0f), 4));
        size_t on_plane = 0;
        for (const auto& x : box.particles.x) on_plane += x.x() == 0.0f ? 1 : 0;
        REQUIRE(on_plane >= 16);
        change = topology::cut(box, plane(Vec3f::Zero(), Vec3f::UnitX()));
        REQUIRE(change.ok());
        require_invariants(box);
        CHECK(change->crossed_edges == 0);
        CHECK(change->duplicated_vertices == on_plane);
        CHECK(change->components_after == 2);
    }

    TEST_CASE("a partial cut opens a slit and stops at its last crossed edge") {
        sim::SoftBody b = test::make_body(mesh::icosphere(3));
        topology::CutSurface s = plane(Vec3f::Zero(), Vec3f(1.0f, 0.0f, 0.2f));
        s.inside = [](const Vec3f& x) { return x.y() > 0.3f; };  // only the cap above y = 0.3
        auto change = topology::cut(b, s);
        REQUIRE(change.ok());
        require_invariants(b);
        CHECK(change->components_after == 1);
        CHECK(change->duplicated_vertices > 0);
        const auto counts = topology::count_components_and_loops(b);
        CHECK(counts.boundary_loops == 1);
        REQUIRE(b.volumes.size() == 1);  // one capped volume over the slit
        CHECK(b.volumes[0].cap_loops.size() == 1);
        // Nothing was split: the piece keeps its label, every particle (the copies too) in it.
        CHECK(b.pieces == 1);
        CHECK(b.volumes[0].piece == 0);
        for (uint32_t p : b.piece_of_particle) REQUIRE(p == 0);
    }

    TEST_CASE("a slit in a large body is settled around it: no whole-piece search, the target as a full sum gives") {
        sim::SoftBody b = test::make_body(mesh::icosphere(5));
        sim::Solver solver;
        sim::SolverSettings s;
        s.gravity = Vec3f::Zero();
        b.volumes[0].pressure = 1.2f;
        for (int f = 0; f < 3; ++f) solver.step(b, 1.0f / 60.0f, s, {}, {});
        REQUIRE(std::isfinite(b.volumes[0].measured_six_v));
        const uint32_t pole = b.extreme_particle(1);
        const float edge = float(b.distance_groups.mean_rest());
        sim::SoftBody exact = b;  // the same slit with no solver measure: the piece summed whole
        exact.volumes[0].measured_six_v = std::numeric_limits<double>::quiet_NaN();
        for (sim::SoftBody* body : {&b, &exact}) {
            for (const topology::VolumePolicy policy : {topology::VolumePolicy::cap}) {
                topology::CutOptions o;
                o.volume = policy;
                auto change = topology::cut(*body, topology::local_cut_on(*body, pole, Vec3f::UnitX(), 3.0f * edge), o);
                REQUIRE(change.ok());
                require_invariants(*body);
                CHECK(change->crossed_triangles > 0);
                CHECK(change->components_after == 1);
                CHECK(change->searched_whole == 0);
                CHECK(change->particles_searched < body->particle_count() / 10);
                CHECK(change->summed_whole == (body == &exact ? 1u : 0u));
            }
        }
        REQUIRE(b.volumes.size() == 1);
        REQUIRE(exact.volumes.size() == 1);
        CHECK(b.volumes[0].cap_loops.size() == 1);
        // The measure is a step old; the target moves by the small cap only, so it barely shows.
        CHECK(b.volumes[0].rest_volume == doctest::Approx(exact.volumes[0].rest_volume).epsilon(1e-4));
    }

    TEST_CASE("a flake cut off a large body is found locally, labelled apart, and the rest keeps its air") {
        sim::SoftBody b = test::make_body(mesh::icosphere(5));
        const uint32_t pole = b.extreme_particle(1);
        const Vec3f top = sim::xyz(b.particles.x[pole]);
        // A plane just under the pole: a small cap comes off.
        auto plane = topology::plane_cut(top - Vec3f(0.0f, 0.05f, 0.0f), Vec3f::UnitY());
        REQUIRE(plane.ok());
        auto change = topology::cut(b, plane.value());
        REQUIRE(change.ok());
        require_invariants(b);
        CHECK(change->components_after == 2);
        CHECK(change->searched_whole == 0);
        CHECK(change->particles_searched < b.particle_count() / 4);
        CHECK(b.piece_of_particle[pole] != b.piece_of_particle[b.extreme_particle(1, false)]);
        // The sphere keeps a constraint; the flat cap holds no air.
        REQUIRE(b.volumes.size() >= 1);
        CHECK(b.volumes[0].piece == b.piece_of_particle[b.extreme_particle(1, false)]);
    }

    TEST_CASE("a large body cut in halves: the smaller half flooded once past the first rings, the larger keeps its label and its air unsummed") {
        sim::SoftBody b = test::make_body(mesh::icosphere(5));
        sim::Solver solver;
        sim::SolverSettings s;
        s.gravity = Vec3f::Zero();
        for (int f = 0; f < 3; ++f) solver.step(b, 1.0f / 60.0f, s, {}, {});
        REQUIRE(std::isfinite(b.volumes[0].measured_six_v));
        sim::SoftBody exact = b;  // the same cut with no solver measure: every part summed
        exact.volumes[0].measured_six_v = std::numeric_limits<double>::quiet_NaN();
        for (sim::SoftBody* body : {&b, &exact}) {
            const size_t n = body->particle_count();
            auto change = topology::cut(*body, plane(Vec3f(0.03f, 0.01f, 0.0f), Vec3f(1.0f, 0.2f, 0.1f)));
            REQUIRE(change.ok());
            require_invariants(*body);
            CHECK(change->components_after == 2);
            // Two halves of 5k particles each: past the first rings around the cut, the search
            // floods the half on the side with fewer particles and stops when it closes: that
            // half and those rings, not the body (no sweep).
            CHECK(change->searched_whole == 0);
            CHECK(change->particles_searched >= n * 2 / 5);
            CHECK(change->particles_searched < n * 3 / 4);
            const auto counts = topology::count_components_and_loops(*body);
            CHECK(counts.components == 2);
        }
        REQUIRE(b.volumes.size() == 2);
        REQUIRE(exact.volumes.size() == 2);
        // The unexplored half's target from the solver's measure less the explored half: the
        // same as summing it, to the measure's age (a step; nothing moves without gravity).
        for (size_t k = 0; k < 2; ++k) {
            CHECK(b.volumes[k].piece == exact.volumes[k].piece);
            CHECK(b.volumes[k].rest_volume == doctest::Approx(exact.volumes[k].rest_volume).epsilon(1e-4));
        }
        CHECK(total_rest_volume(b) == doctest::Approx(total_volume(b)).epsilon(0.01));
    }

    TEST_CASE("a cut that misses the body changes nothing") {
        sim::SoftBody b = test::make_body(mesh::icosphere(2));
        const size_t n = b.particle_count(), t = b.triangles.size();
        auto change = topology::cut(b, plane(Vec3f(5.0f, 0.0f, 0.0f), Vec3f::UnitX()));
        REQUIRE(change.ok());
        CHECK_FALSE(change->changed());
        CHECK(b.particle_count() == n);
        CHECK(b.triangles.size() == t);
    }

    TEST_CASE("cut, then cut the pieces again") {
        sim::SoftBody b = test::make_body(mesh::icosphere(3));
        const double volume = total_volume(b);
        REQUIRE(topology::cut(b, plane(Vec3f(0.03f, 0.0f, 0.0f), Vec3f(1.0f, 0.05f, 0.0f))).ok());
        auto second = topology::cut(b, plane(Vec3f(0.0f, -0.04f, 0.0f), Vec3f(0.02f, 1.0f, 0.1f)));
        REQUIRE(second.ok());
        require_invariants(b);
        CHECK(second->components_before == 2);
        CHECK(second->components_after == 4);
        CHECK(b.volumes.size() == 4);
        // The second cut's loops bend over two planes, so the capped volumes no longer add up to
        // the sphere's; what matters is that no piece jumps: each sits at its target.
        for (size_t k = 0; k < b.volumes.size(); ++k)
            CHECK(b.volume(k) == doctest::Approx(b.volumes[k].rest_volume * b.volumes[k].pressure).epsilon(0.01));
        CHECK(total_volume(b) < volume);
    }

    TEST_CASE("an open sheet cut across splits into two strips; a pinned row stays pinned") {
        sim::SoftBody b = test::make_body(mesh::grid_sheet(16), {.volume = false});
        const uint32_t top = b.extreme_particle(1);
        b.pin(top);
        auto change = topology::cut(b, plane(Vec3f(0.013f, 0.0f, 0.0f), Vec3f::UnitX()));
        REQUIRE(change.ok());
        require_invariants(b);
        CHECK(change->components_after == 2);
        CHECK(b.particles.w[top] == 0.0f);
        CHECK(b.volumes.empty());
    }

    TEST_CASE("one plane through a pinned body and a free one beside it: the pinned one's new particles stay pinned, the free one keeps its mass") {
        // A table (every particle pinned, as a static [[bodies]] entry) and a ball on it, cut by one plane.
        mesh::TriangleMesh m = mesh::box(Vec3f(1.0f, 0.2f, 1.0f), 8);
        mesh::append(m, mesh::icosphere(3, 0.3f), test::moved_by(Vec3f(0.1f, 0.45f, 0.0f)));
        sim::SoftBody b = test::make_body(std::move(m));
        b.model_of_particle = b.piece_of_particle;
        const uint32_t table = b.piece_of_particle[b.extreme_particle(1, false)];
        for (uint32_t i = 0; i < b.particle_count(); ++i)
            if (b.piece_of_particle[i] == table) b.pin(i);
        const double free_mass = total_mass(b);
        const size_t before = b.particle_count();
        REQUIRE(topology::cut(b, plane(Vec3f(0.03f, 0.0f, 0.0f), Vec3f(1.0f, 0.0f, 0.1f))).ok());
        require_invariants(b);
        size_t added_to_table = 0, loose = 0;
        for (size_t i = before; i < b.particle_count(); ++i)
            if (b.model_of_particle[i] == table) ++added_to_table, loose += b.particles.w[i] > 0.0f ? 1 : 0;
        MESSAGE(added_to_table << " particles added to the table, " << loose << " of them free");
        CHECK(added_to_table > 0);
        CHECK(loose == 0);  // 82 came loose, taking the ball's mass, before each model kept its own
        CHECK(total_mass(b) == doctest::Approx(free_mass).epsilon(1e-5));
    }

    TEST_CASE("a cut beside an ear at an opening leaves the ear on its strip, not as a one-triangle fleck") {
        // A sheet of 8 x 4 quads (x right, z up) with one ear (a triangle whose third corner has
        // no other triangle) hanging below the bottom row. The plane just above the bottom row
        // snaps the row onto the cut; left alone, both of the ear's inner corners snap and the
        // cut runs along its inner edge, taking the ear away as a piece of one triangle.
        mesh::TriangleMesh m;
        const uint32_t cols = 8, rows = 4;
        for (uint32_t r = 0; r <= rows; ++r)
            for (uint32_t c = 0; c <= cols; ++c) m.positions.push_back(Vec3f(float(c), 0.0f, float(r)));
        auto at = [&](uint32_t r, uint32_t c) { return r * (cols + 1) + c; };
        for (uint32_t r = 0; r < rows; ++r)
            for (uint32_t c = 0; c < cols; ++c) {
                m.triangles.push_back({at(r, c), at(r, c + 1), at(r + 1, c + 1)});
                m.triangles.push_back({at(r, c), at(r + 1, c + 1), at(r + 1, c)});
            }
        const Vec3f tip(3.5f, 0.0f, -0.8f), far_corner(0.0f, 0.0f, float(rows));
        m.positions.push_back(tip);
        m.triangles.push_back({at(0, 3), uint32_t(m.positions.size() - 1), at(0, 4)});
        // The body orders its particles its own way: the piece is found from a position.
        auto piece_triangles = [](const sim::SoftBody& b, const Vec3f& x) {
            uint32_t v = 0;
            for (uint32_t i = 0; i < b.particle_count(); ++i)
                if ((b.rest_positions[i] - x).norm() < (b.rest_positions[v] - x).norm()) v = i;
            return std::ranges::count_if(b.triangles, [&](const mesh::Triangle& t) { return b.piece_of_particle[t[0]] == b.piece_of_particle[v]; });
        };
        const topology::CutSurface above_row = plane(Vec3f(0.0f, 0.0f, 0.03f), Vec3f::UnitZ());
        {
            sim::SoftBody b = test::make_body(m, {.volume = false});
            topology::CutOptions o;
            o.min_fragment_triangles = 0;  // the snaps as they were: the fleck this guards against
            REQUIRE(topology::cut(b, above_row, o).ok());
            require_invariants(b);
            CHECK(piece_triangles(b, tip) == 1);
        }
        sim::SoftBody b = test::make_body(m, {.volume = false});
        auto change = topology::cut(b, above_row);
        REQUIRE(change.ok());
        require_invariants(b);
        // With its corners unsnapped the ear would keep a strip of four triangles below the row
        // (its own and a child of each first-row triangle the cut crosses beside it): still a
        // fleck, so the strip changes sides and the ear stays on the sheet.
        CHECK(sim::smallest_piece_triangles(b) >= 8);
        CHECK(piece_triangles(b, tip) == piece_triangles(b, far_corner));
        CHECK(piece_triangles(b, far_corner) >= std::ptrdiff_t(2 * cols * (rows - 1)));
    }

    TEST_CASE("a cut that would part a cap of a few triangles from a body passes it by; a larger cap comes off") {
        // The plane across the edges around the highest vertex of icosphere:1, a third of the way
        // down them (no snap reaches that far): the cap is the vertex's five or six triangles.
        const mesh::TriangleMesh m = mesh::icosphere(1);
        const auto at_depth = [&](const sim::SoftBody& b, float rings) {
            uint32_t top = 0;
            for (uint32_t i = 0; i < b.particle_count(); ++i)
                if (b.particles.x[i].y() > b.particles.x[top].y()) top = i;
            const Vec3f n = sim::xyz(b.particles.x[top]).normalized();
            float drop = 1e9f;  // the nearest ring's depth below the top along n
            for (const auto& pair : b.rings.ring.of(top))
                for (uint32_t w : pair) drop = std::min(drop, (sim::xyz(b.particles.x[top]) - sim::xyz(b.particles.x[w])).dot(n));
            return plane(sim::xyz(b.particles.x[top]) - rings * drop * n, n);
        };
        {
            sim::SoftBody b = test::make_body(m);
            topology::CutOptions o;
            o.min_fragment_triangles = 0;  // every cap comes off: the fleck this guards against
            REQUIRE(topology::cut(b, at_depth(b, 0.35f), o).ok());
            require_invariants(b);
            CHECK(b.pieces == 2);
            CHECK(sim::smallest_piece_triangles(b) < 8);  // the vertex's five or six triangles
        }
        sim::SoftBody b = test::make_body(m);
        const size_t particles = b.particle_count();
        REQUIRE(topology::cut(b, at_depth(b, 0.35f), topology::CutOptions{}).ok());
        require_invariants(b);
        CHECK(b.pieces == 1);
        CHECK(b.particle_count() == particles);  // nothing crossed: the body as it was
        // Past the first ring the cap holds the second ring's triangles too: it comes off.
        sim::SoftBody deeper = test::make_body(m);
        REQUIRE(topology::cut(deeper, at_depth(deeper, 1.3f), topology::CutOptions{}).ok());
        require_invariants(deeper);
        CHECK(deeper.pieces == 2);
        CHECK(sim::smallest_piece_triangles(deeper) >= 8);
    }

    TEST_CASE("a plane through a fleck (a piece under 8 triangles) passes it by") {
        // A ball and, beside it, a tetrahedron (what an earlier cut may have left), one plane
        // through both: the ball parts, the fleck stays whole whichever way it is crossed (parted,
        // it made pieces of one or two triangles: 122 pieces of a teapot cut by 40 planes, the
        // smallest of one triangle).
        const auto ball_and_fleck = [] {
            mesh::TriangleMesh m = mesh::icosphere(3, 0.5f);
            mesh::TriangleMesh tetra;
            tetra.positions = {Vec3f(0.0f, -0.1f, -0.1f), Vec3f(0.15f, 0.1f, 0.0f), Vec3f(-0.1f, 0.1f, 0.1f), Vec3f(0.0f, 0.1f, -0.15f)};
            tetra.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
            mesh::append(m, tetra, test::moved_by(Vec3f(1.0f, 0.0f, 0.0f)));
            return test::make_body(std::move(m));
        };
        for (const float tilt : {0.0f, 0.3f, 1.0f}) {
            CAPTURE(tilt);
            const topology::CutSurface cut = plane(Vec3f(0.0f, 0.01f, 0.02f), Vec3f(0.0f, 1.0f, tilt).normalized());
            sim::SoftBody b = ball_and_fleck();
            REQUIRE(b.pieces == 2);
            REQUIRE(topology::cut(b, cut).ok());
            require_invariants(b);
            CHECK(b.pieces == 3);  // the ball's halves and the fleck
            CHECK(sim::smallest_piece_triangles(b) == 4);
            // With no fleck size the tetrahedron parts.
            sim::SoftBody loose = ball_and_fleck();
            topology::CutOptions o;
            o.min_fragment_triangles = 0;
            REQUIRE(topology::cut(loose, cut, o).ok());
            CHECK(loose.pieces == 4);
        }
    }

    TEST_CASE("planes cut through a body again and again leave no fleck") {
        // Forty random planes through a ball and the pieces they make: every piece keeps at
        // least 8 triangles, whatever the snaps met (a teapot cut so had pieces of one triangle).
        sim::SoftBody b = test::make_body(mesh::icosphere(3));
        std::mt19937 rng(7);
        std::uniform_real_distribution<float> u(-1.0f, 1.0f);
        for (int k = 0; k < 40; ++k) {
            const Vec3f n = Vec3f(u(rng), u(rng), u(rng)).normalized(), at = 0.7f * Vec3f(u(rng), u(rng), u(rng));
            REQUIRE(topology::cut(b, plane(at, n)).ok());
        }
        require_invariants(b);
        MESSAGE(b.pieces << " pieces, the smallest of " << sim::smallest_piece_triangles(b) << " triangles");
        CHECK(b.pieces > 20);
        CHECK(sim::smallest_piece_triangles(b) >= 8);
    }

    TEST_CASE("bad input is refused with a reason") {
        sim::SoftBody b = test::make_body(mesh::icosphere(1));
        topology::CutSurface s;
        s.normal = Vec3f(std::nanf(""), 0.0f, 0.0f);
        CHECK_FALSE(topology::cut(b, s).ok());
        CHECK_FALSE(topology::plane_cut(Vec3f::Zero(), Vec3f::Zero()).ok());
        topology::CutOptions o;
        o.snap = 0.7f;
        CHECK_FALSE(topology::cut(b, plane(Vec3f::Zero(), Vec3f::UnitX()), o).ok());
        b.particles.x[3].x() = std::numeric_limits<float>::infinity();
        CHECK_FALSE(topology::cut(b, plane(Vec3f::Zero(), Vec3f::UnitX())).ok());
    }

    TEST_CASE("random cuts in sequence (200, 60 under ASan) keep every invariant, with no NaN") {
#if defined(__SANITIZE_ADDRESS__)
        constexpr int k_cuts = 60;  // ASan runs the bunny's cuts about 3x slower; the release suite runs all 200
#else
        constexpr int k_cuts = 200;
#endif
        std::string spec = "stanford-bunny.obj";
        if (!asset::find_model(spec)) {
            test::skip("the bunny: stanford-bunny.obj not on the model search path; using icosphere:4");
            spec = "icosphere:4";
        }
        auto m = asset::load_mesh_spec(spec);
        REQUIRE_MESSAGE(m.ok(), test::why(m));
        sim::SoftBody b = test::make_body(std::move(m).value().mesh);
        const double mass = total_mass(b);
        std::mt19937 rng(7);
        std::uniform_real_distribution<float> u(-1.0f, 1.0f);
        sim::Solver solver;
        sim::SolverSettings settings;
        settings.gravity = Vec3f::Zero();
        size_t opened = 0, fell_back = 0;
        for (int k = 0; k < k_cuts; ++k) {
            // Through a random particle, so every cut meets the surface.
            const uint32_t at = uint32_t(std::abs(u(rng)) * float(b.particle_count() - 1));
            const Vec3f p = sim::xyz(b.particles.x[at]);
            Vec3f nrm(u(rng), u(rng), u(rng));
            if (nrm.norm() < 0.1f) nrm = Vec3f::UnitX();
            topology::CutSurface s = plane(p, nrm);
            if (k % 2 == 0) {  // half of them partial: a ball around that particle
                const Vec3f c = p;
                const float r = 0.1f + 0.3f * std::abs(u(rng));
                s.inside = [c, r](const Vec3f& x) { return (x - c).squaredNorm() < r * r; };
            }
            auto change = topology::cut(b, s);
            REQUIRE_MESSAGE(change.ok(), test::why(change));
            opened += change->duplicated_vertices > 0 ? 1 : 0;
            fell_back += change->loops_fell_back ? 1 : 0;
            const core::Status st = topology::check_invariants(b);
            REQUIRE_MESSAGE(st.ok(), "after cut " << k << ": " << test::why(st));
            if (k % 20 == 19) solver.step(b, 1.0f / 60.0f, settings, {}, {});
            REQUIRE(std::all_of(b.particles.x.begin(), b.particles.x.end(), [](const Vec4f& x) { return x.allFinite(); }));
        }
        CHECK(opened > size_t(k_cuts) * 3 / 4);
        CHECK(total_mass(b) == doctest::Approx(mass).epsilon(1e-4));
        // The incremental paths ran (check_invariants compared them with full builds after
        // every cut): emptied slots were taken again, new groups were made at the end.
        CHECK(b.distance_groups.slots_reused > 0);
        CHECK(fell_back == 0);  // every cap loop was traced locally
        CHECK(b.distance_groups.slots_appended > 0);
        // Constraints that found no dead slot went into existing colours: hardly any group was
        // made for them, so the solver's passes stay as few as a fresh grouping's.
        CHECK(b.distance_groups.colours_added * 10 < b.distance_groups.slots_appended);
        CHECK(b.distance_groups.start.size() - 1 <= b.distance_groups.colours_when_grouped + 8);
        MESSAGE("slots reused " << b.distance_groups.slots_reused << ", appended " << b.distance_groups.slots_appended
                                << ", regroupings " << b.distance_groups.regroupings << ", colours added "
                                << b.distance_groups.colours_added);
    }

    TEST_CASE("cuts repeated through one small region keep every corner above a sliver") {
        // The long stress suite's finding, in small: cuts crossing the same few triangles again
        // and again shrank a corner piece by a tenth per generation until it broke the sliver
        // invariant (after 723 cuts over a whole sphere). Here every cut is a short slit
        // through a point within half an edge of one vertex, so the region's triangles are
        // re-cut generation after generation. Without the corner rule in topology/cut.cpp, cut
        // 104 of these leaves a triangle of 7.5e-5 of the mean area (checked by disabling it);
        // with it, 400 cuts keep every triangle above 2.4e-4.
        sim::SoftBody b = test::make_body(mesh::icosphere(3));
        const Vec3f centre = sim::xyz(b.particles.x[0]);
        const float edge = b.distance.front().rest;
        std::mt19937 rng(5);
        std::uniform_real_distribution<float> u(-1.0f, 1.0f);
        float smallest = 1.0f;
        for (int k = 0; k < 250; ++k) {
            const Vec3f p = centre + 0.5f * edge * Vec3f(u(rng), u(rng), u(rng));
            Vec3f nrm(u(rng), u(rng), u(rng));
            if (nrm.norm() < 0.1f) nrm = Vec3f::UnitX();
            topology::CutSurface s = plane(p, nrm);
            const float r = 1.5f * edge;
            s.inside = [p, r](const Vec3f& x) { return (x - p).squaredNorm() < r * r; };
            auto change = topology::cut(b, s);
            REQUIRE_MESSAGE(change.ok(), test::why(change));
            const core::Status st = topology::check_invariants(b);
            REQUIRE_MESSAGE(st.ok(), "after cut " << k << ": " << test::why(st));
            double mean = 0.0;
            float least = 1e30f;
            for (const auto& t : b.triangles) {
                const float a = 0.5f * (b.rest_positions[t[1]] - b.rest_positions[t[0]]).cross(b.rest_positions[t[2]] - b.rest_positions[t[0]]).norm();
                mean += a, least = std::min(least, a);
            }
            smallest = std::min(smallest, float(least / (mean / double(b.triangles.size()))));
        }
        MESSAGE("smallest rest triangle after 250 cuts in one region: " << smallest << " of the mean");
    }

    TEST_CASE("a scripted cut sequence is deterministic") {
        auto run = [] {
            sim::SoftBody b = test::make_body(mesh::icosphere(3));
            sim::Solver solver;
            sim::SolverSettings s;
            for (int f = 0; f < 40; ++f) {
                if (f == 10) REQUIRE(topology::cut(b, plane(Vec3f(0.1f, 0.0f, 0.0f), Vec3f(1.0f, 0.2f, 0.1f))).ok());
                if (f == 25) REQUIRE(topology::cut(b, plane(Vec3f(0.0f, 0.1f, 0.0f), Vec3f(0.1f, 1.0f, 0.3f))).ok());
                solver.step(b, 1.0f / 60.0f, s, {}, {});
            }
            return std::pair{sim::state_hash(b.particles), b.triangles.size()};
        };
        CHECK(run() == run());
    }
}
