#include <doctest/doctest.h>

#include <optional>
#include <string>

#include <cmath>
#include <random>

#include "asset/model_path.h"
#include "asset/obj_loader.h"
#include "mesh/decimate.h"
#include "mesh/repair.h"
#include "sim/drag.h"
#include "sim/contact.h"
#include "sim/state_hash.h"
#include "sim/weld.h"
#include "sim_fixtures.h"

#include "support/skip.h"
using namespace pbdsplat;

namespace {
// A model of ../shared/models, repaired, centred and 2 m across; nullopt (and the skip said) where
// the folder is not there.
std::optional<mesh::TriangleMesh> shared_model(const char* file) {
    const auto path = asset::find_model(file);
    if (!path) {
        test::skip(std::string(file) + " not found on the model search path (../shared/models)");
        return std::nullopt;
    }
    auto raw = asset::load_obj(*path);
    REQUIRE(raw.ok());
    mesh::RepairOptions o;
    o.center = true;
    o.fit_diagonal = 2.0f;
    auto rep = mesh::repair(std::move(raw).value(), o, *path);
    REQUIRE(rep.ok());
    return std::move(rep).value().mesh;
}
} // namespace

TEST_SUITE("sim/solver") {
    TEST_CASE("the frame schedule is the paper's order: per substep forces, I x the constraints, velocities; then normals and sleep") {
        sim::SolverSettings s;
        s.iterations = 2;
        s.substeps = 2;
        s.contact.enabled = false;
        auto schedule = sim::frame_schedule(s);
        std::string order;
        for (const auto& e : schedule) order += std::string(sim::stage_name(e.stage)) + " ";
        CHECK(order == "forces distance volume shape drag collide distance volume shape drag collide velocities "
                       "forces distance volume shape drag collide distance volume shape drag collide velocities normals sleep ");
        CHECK(schedule[7].substep == 0);
        CHECK(schedule[7].iteration == 1);
        CHECK(schedule[13].substep == 1);
        // Contact (on by default) searches once a substep after prediction and projects last in
        // every iteration.
        s.contact.enabled = true;
        schedule = sim::frame_schedule(s);
        order.clear();
        for (const auto& e : schedule) order += std::string(sim::stage_name(e.stage)) + " ";
        CHECK(order == "forces contacts distance volume shape drag collide contact distance volume shape drag collide contact velocities "
                       "forces contacts distance volume shape drag collide contact distance volume shape drag collide contact velocities normals sleep ");
        CHECK(schedule[8].iteration == 1);
        CHECK(schedule[15].substep == 1);
        CHECK(sim::stage_group(sim::Stage::collide) == sim::StageGroup::constraints);
        CHECK(sim::stage_group(sim::Stage::normals) == sim::StageGroup::integrate_normals);
    }

    TEST_CASE("linear momentum is conserved without external forces or pins") {
        for (sim::SolverMode mode : {sim::SolverMode::paper, sim::SolverMode::xpbd}) {
            auto b = test::make_body(mesh::icosphere(3));
            std::mt19937 rng(3);
            std::uniform_real_distribution<float> u(-1.0f, 1.0f);
            for (auto& v : b.particles.v) v = Vec4f(u(rng), u(rng), u(rng), 0.0f);
            const Vec3d before = b.particles.linear_momentum();
            sim::SolverSettings s;
            s.mode = mode;
            s.gravity = Vec3f::Zero();
            s.sleep.enabled = false;  // a body drifting slower than sleep's still radius would be held
            test::run(b, 60, 1.0f / 60.0f, s);
            const Vec3d after = b.particles.linear_momentum();
            CHECK((after - before).norm() < 1e-4 * (1.0 + before.norm()));
        }
    }

    // The rotation that best maps `from` onto `to` (mass-weighted, about their centres of mass):
    // what a viewer sees a deforming body turn by.
    double turned_angle(const sim::Vec4Array& from, const sim::SoftBody& b) {
        double m = 0.0;
        Vec3d c = Vec3d::Zero(), c0 = Vec3d::Zero();
        for (size_t i = 0; i < b.particle_count(); ++i) {
            const double mi = 1.0 / double(b.particles.w[i]);
            m += mi, c += mi * sim::xyz(b.particles.x[i]).cast<double>(), c0 += mi * sim::xyz(from[i]).cast<double>();
        }
        c /= m, c0 /= m;
        Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
        for (size_t i = 0; i < b.particle_count(); ++i)
            a += (1.0 / double(b.particles.w[i])) * (sim::xyz(b.particles.x[i]).cast<double>() - c) * (sim::xyz(from[i]).cast<double>() - c0).transpose();
        const Eigen::JacobiSVD<Eigen::Matrix3d> svd(a, Eigen::ComputeFullU | Eigen::ComputeFullV);
        const Eigen::Matrix3d r = svd.matrixU() * svd.matrixV().transpose();
        return std::acos(std::clamp((r.trace() - 1.0) / 2.0, -1.0, 1.0));
    }

    TEST_CASE("a balloon blown up at once with uneven masses neither pushes itself along nor spins") {
        // One side a hundred times lighter than the rest (a model's slivers): the volume pass
        // holds their moves (weight cap) and the stretched fans' (push_share); the impulses it
        // no longer gives them must become neither a net thrust nor a spin.
        for (const float pressure : {3.0f, 100.0f}) {
            CAPTURE(pressure);
            auto b = test::make_body(mesh::icosphere(3));
            for (size_t i = 0; i < b.particle_count(); ++i)
                if (b.particles.x[i].x() > 0.3f) b.particles.w[i] *= 100.0f;
            b.volumes[0].pressure = pressure;
            sim::SolverSettings s;
            s.gravity = Vec3f::Zero();
            s.sleep.enabled = false;
            const sim::Vec4Array start = b.particles.x;
            test::run(b, 60, 1.0f / 60.0f, s);
            double mass = 0.0;
            for (const float w : b.particles.w) mass += 1.0 / double(w);
            const double drift = b.particles.linear_momentum().norm() / mass, angle = turned_angle(start, b);
            MESSAGE("drift " << drift << " m/s, turned " << angle << " rad in 1 s, volume " << b.volume(0) / b.volumes[0].rest_volume);
            // measured: drift 2e-6 m/s with the net impulse taken back (335 m/s without, at 100)
            CHECK(drift < 1e-3);
            // At 100 the paper's five iterations cannot hold this skin: it folds through itself
            // and out again, so only the drift is asked of it.
            if (pressure < 10.0f) {
                // measured: 0.27 rad with the impulses' moment taken back, 0.49 without (what is
                // left comes from PBD's later projections, made at moved positions)
                CHECK(angle < 0.4);
                CHECK(b.volume(0) / b.volumes[0].rest_volume == doctest::Approx(pressure).epsilon(0.02));
            }
        }
    }

    TEST_CASE("a hole rimmed by slivers is not drawn out into a spike when the balloon is blown up") {
        // A ball with a small hole, its rim's particles fifty times lighter than the skin's (a
        // decimated model's slivers: the Stanford bunny's base holes), blown to three times its
        // volume at once. The virtual cap pushes the rim as the skin it stands for would; weighed
        // as the rim's own slivers, it drew the rim out along the cap's normal as a spike.
        mesh::TriangleMesh m = mesh::icosphere(3);
        std::erase_if(m.triangles, [&](const mesh::Triangle& t) {
            return (m.positions[t[0]].y() + m.positions[t[1]].y() + m.positions[t[2]].y()) / 3.0f > 0.9f;
        });
        auto b = test::make_body(std::move(m));
        REQUIRE(b.volumes.size() == 1);
        REQUIRE(b.volumes[0].cap_loops.size() == 1);
        const std::vector<uint32_t> rim = b.volumes[0].cap_loops[0];
        for (const uint32_t i : rim) b.particles.w[i] *= 50.0f;
        b.volumes[0].pressure = 3.0f;
        sim::SolverSettings s;
        s.gravity = Vec3f::Zero();
        s.sleep.enabled = false;
        test::run(b, 60, 1.0f / 60.0f, s);
        REQUIRE(test::all_finite(b));
        // How far the rim stands out: its farthest particle from the centre of mass over the
        // median distance of the skin's.
        Vec3d centre = Vec3d::Zero();
        double mass = 0.0;
        for (size_t i = 0; i < b.particle_count(); ++i) {
            const double mi = 1.0 / double(b.particles.w[i]);
            centre += mi * sim::xyz(b.particles.x[i]).cast<double>(), mass += mi;
        }
        centre /= mass;
        const auto radius = [&](uint32_t i) { return (sim::xyz(b.particles.x[i]).cast<double>() - centre).norm(); };
        std::vector<double> radii;
        for (uint32_t i = 0; i < b.particle_count(); ++i) radii.push_back(radius(i));
        std::nth_element(radii.begin(), radii.begin() + radii.size() / 2, radii.end());
        double rim_out = 0.0;
        for (const uint32_t i : rim) rim_out = std::max(rim_out, radius(i));
        const double standing = rim_out / radii[radii.size() / 2];
        MESSAGE("rim at " << standing << " of the median radius; volume " << b.volume(0) / b.volumes[0].rest_volume << " V0");
        CHECK(standing < 1.15);  // measured 1.04; 1.38 with the cap weighing nothing
        CHECK(b.volume(0) / b.volumes[0].rest_volume == doctest::Approx(3.0).epsilon(0.05));
    }

    TEST_CASE("a pressurised icosphere resting on the ground keeps its volume within 1 % (paper mode)") {
        auto b = test::make_body(mesh::icosphere(3));
        sim::Colliders c;
        c.ground = sim::GroundPlane{Vec3f(0, 1, 0), -1.05f};
        sim::SolverSettings s;  // paper: PBD, I = 5, one step per frame
        test::run(b, 240, 1.0f / 60.0f, s, c);
        REQUIRE(test::all_finite(b));
        const double ratio = b.volume(0) / b.volumes[0].rest_volume;
        MESSAGE("volume after 4 s on the ground: " << ratio << " V0");
        CHECK(std::abs(ratio - 1.0) < 0.01);  // measured 0.9989 V0
        // It rests on the ground rather than falling through.
        float lowest = 1e9f;
        for (const auto& x : b.particles.x) lowest = std::min(lowest, x.y());
        CHECK(lowest > -1.06f);  // the ground is at -1: on it, not through (a landing sinks less than an edge)
        CHECK(lowest < -1.0f);  // the ground is at -1
    }

    TEST_CASE("a balloon with next to no stretch stiffness sags on the ground without growing spikes") {
        // The softest stretch a scene may set, no shape matching: only the volume holds the
        // bunny's skin up. The volume pass moves each particle along its area-weighted normal,
        // so where the decimated mesh's large triangles stretched they took ever more of the
        // push, and sheets metres long grew out of it within a second.
        const auto fine = shared_model("stanford-bunny.obj");
        if (!fine) return;
        auto coarse = mesh::decimate(*fine, mesh::DecimateOptions{}, "stanford-bunny.obj");
        REQUIRE(coarse.ok());
        auto b = test::make_body(std::move(coarse).value().mesh);
        float top = -INFINITY, bottom = INFINITY;
        for (const auto& x : b.particles.x) top = std::max(top, x.y()), bottom = std::min(bottom, x.y());
        sim::Colliders c;
        c.ground = sim::GroundPlane{Vec3f(0, 1, 0), bottom - 0.01f};
        sim::SolverSettings s;
        s.stretch_stiffness = 1e-4f;
        float highest = -INFINITY;
        for (int frame = 0; frame < 60; ++frame) {
            test::run(b, 1, 1.0f / 60.0f, s, c);
            for (const auto& x : b.particles.x) highest = std::max(highest, x.y());
        }
        REQUIRE(test::all_finite(b));
        const double ratio = b.volume(0) / b.volumes[0].rest_volume;
        MESSAGE("highest particle over the second: " << (highest - bottom) / (top - bottom) << " of the bunny's height; volume " << ratio << " V0");
        CHECK(highest - bottom < 1.1f * (top - bottom));  // measured 0.998 of its height; with the push unlimited 4.85
        CHECK(ratio > 0.9);  // measured 0.996 V0
    }

    TEST_CASE("a soft balloon firms up slowly when contact steps its frames finer than the scene's") {
        // PBD holds firmer at more substeps: a balloon lying in the sag of one substep a frame
        // sprang up within a frame once contact stepped it in four.
        sim::SoftBody rested = test::make_body(mesh::icosphere(4, 0.45f));
        sim::Colliders c;
        c.ground = sim::GroundPlane{Vec3f(0, 1, 0), -0.47f};
        sim::SolverSettings s;
        s.iterations = 10, s.sleep.enabled = false;
        const auto height = [](const sim::SoftBody& b) {
            float lo = INFINITY, hi = -INFINITY;
            for (const auto& x : b.particles.x) lo = std::min(lo, x.y()), hi = std::max(hi, x.y());
            return hi - lo;
        };
        test::run(rested, 240, 1.0f / 60.0f, s, c);
        const float at_one = height(rested);
        // Two seconds at four substeps a frame, with the stiffness meant at `tuned`: its height
        // after a frame and at the end, and its fastest particle.
        struct Rise {
            float first = 0.0f, last = 0.0f, top_speed = 0.0f;
        };
        const auto four = [&](uint32_t tuned) {
            sim::SoftBody b = rested;
            sim::SolverSettings raised = s;
            raised.tuned_substeps = tuned, raised.substeps = 4;
            sim::Solver solver;
            Rise r;
            for (int f = 0; f < 120; ++f) {
                solver.step(b, 1.0f / 60.0f, raised, c, sim::DragConstraint{});
                for (const auto& v : b.particles.v) r.top_speed = std::max(r.top_speed, v.norm());
                if (f == 0) r.first = height(b);
            }
            REQUIRE(test::all_finite(b));
            r.last = height(b);
            return r;
        };
        const Rise slowly = four(1), at_once = four(4);
        MESSAGE("height at one substep " << at_one << " m; at four tuned at one " << slowly.first << " m after a frame, " << slowly.last
                                         << " m after 2 s (fastest particle " << slowly.top_speed << " m/s); tuned at four " << at_once.first
                                         << " m, " << at_once.last << " m (" << at_once.top_speed << " m/s)");
        CHECK(at_one < 0.8f * 0.9f);                            // it does sag: measured 0.59 m of 0.9
        CHECK(slowly.first < 1.02f * at_one);                   // measured 1.00x
        CHECK(slowly.last > 1.15f * at_one);                    // it does firm up: measured 1.29x
        CHECK(slowly.top_speed < 0.7f);                         // measured 0.49 m/s
        CHECK(at_once.top_speed > 4.0f * slowly.top_speed);     // measured 4.3 m/s
    }

    TEST_CASE("deflating and re-inflating follows the pressure factor") {
        auto b = test::make_body(mesh::icosphere(3));
        sim::SolverSettings s;
        s.gravity = Vec3f::Zero();
        b.volumes[0].pressure = 0.6f;
        test::run(b, 120, 1.0f / 60.0f, s);
        CHECK(b.volume(0) / b.volumes[0].rest_volume == doctest::Approx(0.6).epsilon(0.02));
        b.volumes[0].pressure = 1.0f;
        test::run(b, 120, 1.0f / 60.0f, s);
        CHECK(b.volume(0) / b.volumes[0].rest_volume == doctest::Approx(1.0).epsilon(0.01));
    }

    TEST_CASE("XPBD stretch of a hanging chain hardly depends on the iteration count") {
        // 20 links of 5 cm, 10 g each, compliance 2e-3 m/N, top pinned, 2 s, 8 substeps.
        auto chain_length = [](uint32_t iterations) {
            sim::SoftBody b;
            const int n = 21;
            b.particles.resize(n);
            for (int i = 0; i < n; ++i) {
                b.particles.x[size_t(i)] = Vec4f(0, -0.05f * float(i), 0, 0);
                b.particles.w[size_t(i)] = i == 0 ? 0.0f : 1.0f / 0.01f;  // 10 g each
            }
            for (uint32_t i = 0; i + 1 < uint32_t(n); ++i) b.distance.push_back({i, i + 1, 0.05f, 2e-3f});
            sim::rebuild_derived(b);
            sim::SolverSettings s;
            s.mode = sim::SolverMode::xpbd;
            s.substeps = 8;
            s.iterations = iterations;
            s.damping = 2.0f;
            test::run(b, 120, 1.0f / 60.0f, s);
            return double(-b.particles.x[size_t(n - 1)].y());
        };
        const double rest = 1.0, l5 = chain_length(5), l50 = chain_length(50);
        const double stretch5 = l5 - rest, stretch50 = l50 - rest;
        // Link k from the bottom carries k * m * g; each stretches by tension * compliance.
        const double analytic = 0.01 * 9.81 * 2e-3 * (20.0 * 21.0 / 2.0);
        MESSAGE("stretch at I=5: " << stretch5 << " m, I=50: " << stretch50 << " m, analytic " << analytic << " m");
        CHECK(stretch50 == doctest::Approx(analytic).epsilon(0.1));
        for (uint32_t it : {10u, 20u}) CHECK(std::abs((chain_length(it) - rest) - stretch50) < 0.05 * stretch50);  // measured within 0.01 % of I=50 (0.04387 m)
        CHECK(std::abs(stretch5 - stretch50) < 0.05 * stretch50);  // measured within 0.01 %
    }

    TEST_CASE("no NaN or Inf for time steps from 1/240 s to 1/15 s") {
        for (float dt : {1.0f / 240.0f, 1.0f / 60.0f, 1.0f / 30.0f, 1.0f / 15.0f})
            for (sim::SolverMode mode : {sim::SolverMode::paper, sim::SolverMode::xpbd}) {
                auto b = test::make_body(mesh::icosphere(3));
                b.pin(b.extreme_particle(1));
                sim::Colliders c;
                c.ground = sim::GroundPlane{Vec3f(0, 1, 0), -2.0f};
                c.spheres.push_back({Vec3f(0.3f, -1.5f, 0), 0.4f});
                sim::SolverSettings s;
                s.mode = mode;
                test::run(b, 90, dt, s, c);
                CHECK_MESSAGE(test::all_finite(b), "dt = " << dt);
            }
    }

    TEST_CASE("collisions keep particles out of spheres and boxes") {
        auto b = test::make_body(mesh::icosphere(2, 0.3f));
        for (auto& x : b.particles.x) x += Vec4f(0, 1.5f, 0, 0);
        b.particles.x_prev = b.particles.x;
        sim::Colliders c;
        c.spheres.push_back({Vec3f(0.1f, 0.2f, 0), 0.5f});
        c.boxes.push_back({Vec3f(0, -1.0f, 0), Vec3f(2, 0.3f, 2), Quatf(Eigen::AngleAxisf(0.2f, Vec3f::UnitZ()))});
        sim::SolverSettings s;
        test::run(b, 180, 1.0f / 60.0f, s, c);
        for (const auto& x : b.particles.x) {
            CHECK((sim::xyz(x) - c.spheres[0].center).norm() >= c.spheres[0].radius - 1e-3f);
            const Vec3f local = c.boxes[0].rotation.conjugate() * (sim::xyz(x) - c.boxes[0].center);
            CHECK(((local.cwiseAbs() - c.boxes[0].half_extents).array() >= -1e-3f).any());
        }
    }

    TEST_CASE("dragging pulls the picked particle to the target; releasing lets go") {
        auto b = test::make_body(mesh::icosphere(3));
        const auto picked = sim::pick_particle(b.particles, Vec3f(0, 0, 5), Vec3f(0, 0, -1), 0.1f);
        REQUIRE(picked.has_value());
        CHECK(b.particles.x[*picked].z() > 0.9f);  // the front of the sphere, not the back
        sim::DragConstraint drag = sim::grab_region(b, *picked, 0.0f, 0.5f);
        drag.target = Vec3f(0, 0, 2);
        sim::SolverSettings s;
        s.gravity = Vec3f::Zero();
        sim::Solver solver;
        for (int f = 0; f < 60; ++f) solver.step(b, 1.0f / 60.0f, s, {}, drag);
        CHECK(b.particles.x[*picked].z() > 1.5f);  // the target is at 2 after 60 frames
        CHECK_FALSE(sim::pick_particle(b.particles, Vec3f(5, 5, 5), Vec3f(1, 0, 0), 0.1f).has_value());
    }

    TEST_CASE("a region grab at full stiffness moves the held cap as one, and the body stretches after it") {
        auto b = test::make_body(mesh::icosphere(3));
        for (uint32_t i = 0; i < b.particle_count(); ++i)
            if (b.particles.x[i].y() < -0.9f) b.pin(i);
        const uint32_t top = b.extreme_particle(1);
        const float radius = 0.4f;
        sim::DragConstraint drag = sim::grab_region(b, top, radius, 1.0f);
        REQUIRE(drag.particles.size() > 10);  // a patch, not a particle
        for (size_t k = 0; k < drag.particles.size(); ++k) {
            CHECK(drag.offsets[k].norm() < radius);
            CHECK(drag.weights[k] <= 1.0f);  // the grabs stiffness (1.0) times a smoothstep
            if (drag.offsets[k].norm() <= 0.5f * radius) CHECK(drag.weights[k] == 1.0f);
        }
        sim::SolverSettings s;
        s.gravity = Vec3f::Zero();
        sim::Solver solver;
        const Vec3f grab = drag.target;
        for (int f = 0; f < 60; ++f) {
            drag.target = grab + Vec3f(0.0f, 0.5f * float(f + 1) / 60.0f, 0.0f);
            solver.step(b, 1.0f / 60.0f, s, {}, drag);
        }
        float worst = 0.0f;
        for (size_t k = 0; k < drag.particles.size(); ++k)
            if (drag.offsets[k].norm() <= 0.5f * radius)
                worst = std::max(worst, (sim::xyz(b.particles.x[drag.particles[k]]) - (drag.target + drag.offsets[k])).norm());
        MESSAGE("the held core's largest distance from its place in the moved cap: " << worst);
        CHECK(worst < 1e-3f);
        // The bottom pinned, the cap 0.5 higher: the sphere is drawn out between them.
        const float height = b.particles.x[top].y() - b.particles.x[b.extreme_particle(1, false)].y();
        MESSAGE("height after the pull " << height);
        CHECK(height > 2.4f);  // measured 2.5: the sphere plus the pull of 0.5
    }

    TEST_CASE("a drag leaves a piece pinned whole (a static body) as it stands, and moves a pin of a free one") {
        auto b = test::make_body(mesh::icosphere(3));
        const uint32_t top = b.extreme_particle(1);
        for (uint32_t i = 0; i < b.particle_count(); ++i) b.pin(i);
        CHECK_FALSE(sim::grab_region(b, top, 0.4f, 1.0f).active);  // dragged, its top was drawn up as a spike
        // One particle free: the piece is not static, and its pins may be dragged as before.
        b.particles.w[b.extreme_particle(1, false)] = 1.0f;
        const sim::DragConstraint drag = sim::grab_region(b, top, 0.4f, 1.0f);
        CHECK(drag.active);
        CHECK(drag.particles.size() > 10);
    }

    TEST_CASE("welds hold an open part where it touches another part of its model; closed parts are not welded") {
        // A sheet lying on a box's top face (separate surfaces, one model), the box pinned.
        auto build = [](bool sheet) {
            mesh::TriangleMesh m = mesh::box(Vec3f(1, 1, 1), 4);
            if (sheet) mesh::append(m, mesh::grid_sheet(4, 0.5f), Eigen::Affine3f(Eigen::Translation3f(0.0f, 0.5f, 0.0f)));
            else mesh::append(m, mesh::icosphere(2, 0.25f), Eigen::Affine3f(Eigen::Translation3f(0.0f, 0.75f, 0.0f)));
            sim::SoftBody b = test::make_body(std::move(m));
            REQUIRE(b.pieces == 2);
            for (uint32_t i = 0; i < b.particle_count(); ++i)
                if (b.part_of_particle[i] == b.part_of_particle[b.extreme_particle(1, false)]) b.pin(i);
            return b;
        };
        sim::SoftBody ball = build(false);
        CHECK(sim::weld_touching_parts(ball, sim::mean_rest_edge(ball)) == 0);
        auto run = [](sim::SoftBody b, bool weld) {
            const size_t welds = weld ? sim::weld_touching_parts(b, sim::mean_rest_edge(b)) : 0;
            sim::SolverSettings s;
            s.contact.enabled = false;
            sim::Solver solver;
            for (int f = 0; f < 60; ++f) solver.step(b, 1.0f / 60.0f, s, {}, {});
            float lowest = INFINITY;
            for (uint32_t i = 0; i < b.particle_count(); ++i)
                if (b.part_of_particle[i] != b.part_of_particle[b.extreme_particle(1, false)]) lowest = std::min(lowest, b.particles.x[i].y());
            MESSAGE(std::string(weld ? "welded" : "loose") << " (" << welds << " welds): the sheet's lowest point after 1 s " << lowest);
            return lowest;
        };
        const sim::SoftBody sheet = build(true);
        CHECK(run(sheet, true) > 0.3f);   // its rim is held on the box (its middle sags 6 cm: contact is off)
        CHECK(run(sheet, false) < 0.0f);  // nothing holds it: it falls past the box's top
    }

    TEST_CASE("a solid's closed parts that touch are welded too: a ball on a box's top is held there as one object") {
        // A table's legs under its top: closed parts, one model. Welded from open edges only
        // (a balloon's eyes), nothing holds them; from closed parts too, they are one cluster.
        mesh::TriangleMesh m = mesh::box(Vec3f(1, 1, 1), 4);
        mesh::append(m, mesh::icosphere(2, 0.25f), Eigen::Affine3f(Eigen::Translation3f(0.0f, 0.75f, 0.0f)));
        sim::SoftBodyDesc d;
        d.shape_matching = true;
        sim::SoftBody b = test::make_body(std::move(m), d);
        REQUIRE(b.pieces == 2);
        const uint32_t box_part = b.part_of_particle[b.extreme_particle(1, false)];
        for (uint32_t i = 0; i < b.particle_count(); ++i)
            if (b.part_of_particle[i] == box_part) b.pin(i);
        sim::SoftBody open_only = b;
        CHECK(sim::weld_touching_parts(open_only, sim::mean_rest_edge_of_models(open_only), sim::WeldFrom::open_edges) == 0);
        const size_t welds = sim::weld_touching_parts(b, sim::mean_rest_edge_of_models(b), sim::WeldFrom::open_edges_and_closed_parts);
        CHECK(welds > 0);
        for (const sim::DistanceConstraint& w : b.welds) CHECK(b.part_of_particle[w.i] != b.part_of_particle[w.j]);
        sim::rebuild_shape_clusters(b);
        CHECK(b.shapes.size() == 1);
        auto lowest_after_a_second = [&](sim::SoftBody body) {
            sim::SolverSettings s;
            s.contact.enabled = false;
            s.shape_stiffness = 0.9f;
            sim::Solver solver;
            for (int f = 0; f < 60; ++f) solver.step(body, 1.0f / 60.0f, s, {}, {});
            float lowest = INFINITY;
            for (uint32_t i = 0; i < body.particle_count(); ++i)
                if (body.part_of_particle[i] != box_part) lowest = std::min(lowest, body.particles.x[i].y());
            return lowest;
        };
        const float held = lowest_after_a_second(b), loose = lowest_after_a_second(open_only);
        MESSAGE(welds << " welds; the ball's lowest point after 1 s: " << held << " welded, " << loose << " loose");
        CHECK(held > 0.45f);  // it rests at 0.5
        CHECK(loose < 0.0f);  // contact is off: it falls through the box
    }

    TEST_CASE("welded parts are one shape-matching cluster: a ledge welded to a box's side does not hinge down") {
        // A sheet a metre long standing out from a pinned box's +x face, its inner edge on the
        // face (a spout on a pot): welded into the box's cluster it keeps level; in a cluster of
        // its own, its welds are a hinge and it swings down to hang from them.
        auto build = [] {
            mesh::TriangleMesh m = mesh::box(Vec3f(1, 1, 1), 4);
            mesh::append(m, mesh::grid_sheet(8, 1.0f), Eigen::Affine3f(Eigen::Translation3f(1.0f, 0.0f, 0.0f)));
            sim::SoftBodyDesc d;
            d.shape_matching = true;
            sim::SoftBody b = test::make_body(std::move(m), d);
            REQUIRE(b.pieces == 2);
            REQUIRE(b.shapes.size() == 2);
            for (uint32_t i = 0; i < b.particle_count(); ++i)
                if (b.part_of_particle[i] == b.part_of_particle[b.extreme_particle(0, false)]) b.pin(i);
            REQUIRE(sim::weld_touching_parts(b, sim::mean_rest_edge_of_models(b)) > 0);
            return b;
        };
        auto drop = [](sim::SoftBody b) {
            sim::SolverSettings s;
            s.contact.enabled = false;
            s.shape_stiffness = 0.9f;
            sim::Solver solver;
            for (int f = 0; f < 60; ++f) solver.step(b, 1.0f / 60.0f, s, {}, {});
            const uint32_t tip = b.extreme_particle(0);
            return -b.particles.x[tip].y();
        };
        sim::SoftBody joined = build();
        sim::rebuild_shape_clusters(joined);
        CHECK(joined.shapes.size() == 1);
        sim::SoftBody apart = build();  // the clusters built before the welds: one per part
        CHECK(apart.shapes.size() == 2);
        const float joined_drop = drop(joined), apart_drop = drop(apart);
        MESSAGE("the ledge's tip after 1 s: " << joined_drop << " m down welded into one cluster, " << apart_drop << " one cluster a part");
        CHECK(joined_drop < 0.05f);  // measured 0.0003: level
        CHECK(apart_drop > 0.3f);  // measured 0.5: hanging
    }

    TEST_CASE("welds reach by each model's own edge: a small model beside does not leave a large one's parts unwelded") {
        // A sheet on a box's top (one model, edges 0.25) and a fine ball far away (another model,
        // edges about 0.02): one mean edge over both is the ball's, shorter than the sheet's gap
        // to the box's vertices, and welds nothing.
        mesh::TriangleMesh m = mesh::box(Vec3f(1, 1, 1), 4);
        mesh::append(m, mesh::grid_sheet(3, 0.5f), Eigen::Affine3f(Eigen::Translation3f(0.02f, 0.52f, 0.03f)));
        const size_t first_ball = m.positions.size();
        mesh::append(m, mesh::icosphere(5, 0.15f), Eigen::Affine3f(Eigen::Translation3f(3.0f, 0.0f, 0.0f)));
        sim::SoftBodyDesc d;
        d.reorder = false;
        sim::SoftBody b = test::make_body(std::move(m), d);
        REQUIRE(b.pieces == 3);
        b.model_of_particle.assign(b.particle_count(), 0);
        for (size_t i = first_ball; i < b.particle_count(); ++i) b.model_of_particle[i] = 1;
        const std::vector<float> reach = sim::mean_rest_edge_of_models(b);
        REQUIRE(reach.size() == 2);
        CHECK(reach[1] < 0.25f * reach[0]);  // measured 0.02 of it
        sim::SoftBody one_reach = b;
        CHECK(sim::weld_touching_parts(one_reach, sim::mean_rest_edge(one_reach)) == 0);
        CHECK(sim::weld_touching_parts(b, reach) > 0);
        for (const sim::DistanceConstraint& w : b.welds) CHECK(b.model_of_particle[w.i] == 0);
    }

    TEST_CASE("determinism: the same scene gives bit-identical state") {
        auto run_hash = [](float pressure) {
            auto b = test::make_body(mesh::icosphere(3));
            b.pin(b.extreme_particle(1));
            for (auto& v : b.volumes) v.pressure = pressure;
            sim::Colliders c;
            c.ground = sim::GroundPlane{Vec3f(0, 1, 0), -1.5f};
            sim::SolverSettings s;
            test::run(b, 100, 1.0f / 60.0f, s, c);
            return sim::state_hash(b.particles);
        };
        const uint64_t a = run_hash(1.0f), b = run_hash(1.0f), c = run_hash(0.9f);
        CHECK(a == b);
        CHECK(a != c);
    }

    TEST_CASE("determinism: the thread count does not change the result") {
        auto run_hash = [](unsigned threads, sim::SolverMode mode) {
            auto b = test::make_body(mesh::icosphere(5));  // large enough that every stage splits
            b.pin(b.extreme_particle(1));
            sim::Colliders c;
            c.ground = sim::GroundPlane{Vec3f(0, 1, 0), -1.2f};
            sim::SolverSettings s;
            s.mode = mode;
            s.substeps = 2;
            core::ThreadPool pool(threads);
            sim::Solver solver(&pool);
            for (int f = 0; f < 30; ++f) solver.step(b, 1.0f / 60.0f, s, c, {});
            return sim::state_hash(b.particles);
        };
        for (sim::SolverMode mode : {sim::SolverMode::paper, sim::SolverMode::xpbd}) {
            const uint64_t one = run_hash(1, mode);
            CHECK(run_hash(2, mode) == one);
            CHECK(run_hash(3, mode) == one);
        }
    }

    TEST_CASE("impossible settings are refused") {
        sim::SolverSettings s;
        s.iterations = 0;
        CHECK_FALSE(sim::validate(s).ok());
        s = {};
        s.gravity.x() = std::nanf("");
        CHECK_FALSE(sim::validate(s).ok());
        s = {};
        s.stretch_stiffness = 1.5f;
        CHECK_FALSE(sim::validate(s).ok());
        CHECK(sim::validate(sim::SolverSettings{}).ok());
    }

    TEST_CASE("every shared model loads and runs 120 frames (20 under ASan)") {
#if defined(__SANITIZE_ADDRESS__)
        // Every stage runs on every model from the first frame; at 120 frames the full-resolution
        // models took most of this suite's 282 s under ASan (8.3 s in release, 1.1 at 20 frames).
        // 20 frames end before the landing (at 40 a model is caught mid-landing, its volume 0.81
        // of its rest), which the release suite checks.
        constexpr int k_frames = 20;
#else
        constexpr int k_frames = 120;
#endif
        for (const char* file : {"suzanne.obj", "teapot.obj", "stanford-bunny.obj", "fandisk.obj"}) {
            auto fine = shared_model(file);
            if (!fine) continue;
            auto b = test::make_body(std::move(*fine));
            const double v0 = b.volumes.empty() ? 0.0 : b.volume(0);
            sim::Colliders c;
            c.ground = sim::GroundPlane{Vec3f(0, 1, 0), -1.2f};
            test::run(b, k_frames, 1.0f / 60.0f, sim::SolverSettings{}, c);
            CHECK_MESSAGE(test::all_finite(b), file);
            if (v0 > 0.0) CHECK_MESSAGE(std::abs(b.volume(0) / v0 - 1.0) < 0.05, file << ": volume " << b.volume(0) / v0);  // measured 0.9989 V0 for the icosphere above
        }
    }
}
