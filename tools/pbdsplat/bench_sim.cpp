#include "core/timer.h"
#include "asset/mesh_spec.h"
#include "pbdsplat/bench_suites.h"
#include "pbdsplat/sim_baseline.h"
#include "sim/solver.h"
#include "splat/gaussian_record.h"

namespace pbdsplat::cli {

namespace {

const CommandSpec& command_spec() {
    static const CommandSpec command{
        "bench sim", "",
        "Runs Stage A (the CPU PBD frame of the paper) on a body hanging under gravity\n"
        "and prints the median milliseconds per frame, in total and per stage as the paper's\n"
        "Tables 3 and 4 break them down: apply forces, constraint projection, integrate + normals,\n"
        "and update particles (the particle-to-Gaussian mapping).\n",
        {text("mesh", "SPEC", "icosphere:5",
              "icosphere:L, uvsphere:R:S, torus:S:T, box:D, capsule:R:S, grid:N, or an OBJ file\n"
              "or model name (teapot.obj)"),
         choice("pin", {"top", "none"}, "top", "pin the highest particle, or none"),
         named<sim::SolverMode>("mode", sim::k_solver_mode_names, sim::SolverMode::paper, "solver: PBD (paper) or XPBD"),
         whole("iterations", "I", 5, 1, 1000, "constraint iterations per step"),
         whole("substeps", "S", 1, 1, 1000, "steps per frame"),
         whole("frames", "N", 300, 1, 1000000, "measured frames at 60 Hz"),
         whole("warmup", "K", 30, 0, 1000000, "unmeasured frames first"),
         choice("volume", {"on", "off"}, "on", "project the volume constraint"),
         whole("threads", "T", 1, 1, 64, "worker threads, the caller included"),
         flag("baseline", "also run two hand-written loops of the same workload (PBD, one\n"
                          "thread, distance constraints, one volume constraint;\n"
                          "tools/pbdsplat/sim_baseline.h): a plain one in edge order and a tuned\n"
                          "one, frame for frame alternated with the engine, and print the ratio\n"
                          "of the engine's step to each (paper mode; the engine then runs\n"
                          "without the fold guard, a contact stage the loops do not have)"),
         json_option()}};
    return command;
}

Outcome measure(const Options& opt) {
    const uint32_t iterations = opt.whole("iterations"), substeps = opt.whole("substeps"), frames = opt.whole("frames");
    const uint32_t warmup = opt.whole("warmup"), threads = opt.whole("threads");
    const std::string& spec = opt.text("mesh");

    auto repaired = asset::load_mesh_spec(spec);
    if (!repaired.ok()) return repaired.error();
    sim::SoftBodyDesc desc;
    desc.volume = opt.text("volume") == "on";
    auto made = sim::make_soft_body(std::move(repaired).value().mesh, desc);
    if (!made.ok()) return made.error();
    sim::SoftBody body = std::move(made).value();
    if (opt.text("pin") == "top") body.pin(body.extreme_particle(1));

    sim::SolverSettings settings;
    settings.mode = opt.named<sim::SolverMode>("mode", sim::k_solver_mode_names);
    settings.iterations = iterations;
    settings.substeps = substeps;
    settings.volume = desc.volume;
    if (auto v = sim::validate(settings); !v.ok()) return Outcome::usage(v.error().to_string());
    const bool with_baseline = opt.flag("baseline");
    if (with_baseline && settings.mode != sim::SolverMode::paper) return Outcome::usage("--baseline runs PBD: use --mode paper");
    // The same workload as the loops: they keep no fold apart (its cost is measured without
    // --baseline, docs/BENCHMARKS.md, "Surfaces through each other").
    if (with_baseline) settings.contact.folds = false;
    // The yardstick runs on the body's own particle order and pin.
    mesh::TriangleMesh as_body;
    as_body.positions = body.rest_positions;
    as_body.triangles = body.triangles;
    SimBaseline::Settings bs;
    bs.gravity = settings.gravity, bs.damping = settings.damping, bs.stretch_stiffness = settings.stretch_stiffness;
    bs.volume_stiffness = settings.volume_stiffness, bs.iterations = settings.iterations * settings.substeps, bs.volume = desc.volume;
    uint32_t pinned = UINT32_MAX;
    for (uint32_t i = 0; i < body.particle_count(); ++i)
        if (body.particles.w[i] == 0.0f) pinned = i;
    SimBaseline baseline(as_body, pinned, bs);
    bs.tuned = true;
    SimBaseline tuned(as_body, pinned, bs);
    std::vector<double> engine_step, baseline_step, tuned_step;

    core::ThreadPool pool(threads);
    sim::Solver solver(&pool);
    splat::Appearance look;
    std::vector<splat::GaussianRecord> records;
    std::vector<double> total, forces, constraints, integrate, update;
    for (uint32_t f = 0; f < warmup + frames; ++f) {
        const sim::StageTimings t = solver.step(body, 1.0f / 60.0f, settings, {}, {});
        core::Stopwatch clock;
        splat::map_points(body.particles.x, body.normals, look, records);
        const double up = clock.elapsed_ms();
        if (f < warmup) continue;
        if (with_baseline) {
            // Alternated frame for frame, so the machine's drift falls on all three alike.
            const auto time_frame = [&](SimBaseline& loop, std::vector<double>& ms) {
                const core::Stopwatch loop_clock;
                for (uint32_t k = 0; k < settings.substeps; ++k) loop.step(1.0f / 60.0f / float(settings.substeps));
                ms.push_back(loop_clock.elapsed_ms());
            };
            time_frame(baseline, baseline_step);
            time_frame(tuned, tuned_step);
        }
        engine_step.push_back(t.total());
        total.push_back(t.total() + up);
        forces.push_back(t.apply_forces);
        constraints.push_back(t.constraints);
        integrate.push_back(t.integrate_normals);
        update.push_back(up);
    }
    for (const auto& x : body.particles.x)
        if (!x.allFinite()) return core::make_error("the simulation produced NaN or Inf; the settings are unstable");

    const size_t n_constraints = body.distance.size() + (settings.volume ? body.volumes.size() : 0);
    Report report("sim");
    report.json().update({{"mesh", spec},
                          {"mode", opt.text("mode")},
                          {"iterations", iterations},
                          {"substeps", substeps},
                          {"volume", desc.volume},
                          {"threads", threads},
                          {"particles", body.particle_count()},
                          {"constraints", n_constraints},
                          {"frames", frames},
                          {"median_ms", core::median(total)},
                          {"stages_median_ms", {{"apply_forces", core::median(forces)},
                                                {"constraint_projection", core::median(constraints)},
                                                {"integrate_normals", core::median(integrate)},
                                                {"update_particles", core::median(update)}}}});
    report.line(format("%s: %zu particles, %zu distance + %zu volume constraints; %s, I=%u, S=%u, %u thread(s)", spec.c_str(),
                       body.particle_count(), body.distance.size(), settings.volume ? body.volumes.size() : 0,
                       opt.text("mode").c_str(), iterations, substeps, threads));
    report.figures(format("median of %u frames:", frames),
                   {{"apply forces", core::median(forces), "ms"},
                    {"constraint projection", core::median(constraints), "ms"},
                    {"integrate + normals", core::median(integrate), "ms"},
                    {"update particles", core::median(update), "ms (particle-to-Gaussian mapping)"},
                    {"Stage A frame", core::median(total), "ms"}});
    if (with_baseline) {
        const double engine = core::median(engine_step), loop = core::median(baseline_step), fast = core::median(tuned_step);
        const double ratio = engine / std::max(1e-9, loop), tuned_ratio = engine / std::max(1e-9, fast);
        // The same workload: after the same frames the loops' bodies lie where the engine's does,
        // up to the order of their Gauss-Seidel sweeps (the body's size for scale).
        float size = 0.0f, plain_apart = 0.0f, tuned_apart = 0.0f;
        for (uint32_t i = 0; i < body.particle_count(); ++i) {
            const Vec4f x(body.particles.x[i].x(), body.particles.x[i].y(), body.particles.x[i].z(), 0.0f);
            if (!tuned.positions()[i].allFinite()) return core::make_error("the tuned baseline loop produced NaN or Inf");
            size = std::max(size, (body.rest_positions[i] - body.rest_positions[0]).norm());
            plain_apart = std::max(plain_apart, (baseline.positions()[i] - x).norm());
            tuned_apart = std::max(tuned_apart, (tuned.positions()[i] - x).norm());
        }
        report.json()["baseline"] = {{"engine_step_median_ms", engine}, {"baseline_median_ms", loop}, {"ratio", ratio},
                                     {"tuned_median_ms", fast}, {"tuned_ratio", tuned_ratio},
                                     {"plain_apart_per_size", plain_apart / std::max(size, 1e-12f)},
                                     {"tuned_apart_per_size", tuned_apart / std::max(size, 1e-12f)}};
        report.figures("baselines (hand-written loops, same workload, alternated):",
                       {{"engine step", engine, "ms"}, {"plain loop", loop, "ms"}, {"ratio to plain", ratio, "", 2},
                        {"tuned loop", fast, "ms"}, {"ratio to tuned", tuned_ratio, "", 2},
                        {"plain loop's body from the engine's", plain_apart / std::max(size, 1e-12f), "of its size (largest)", 4},
                        {"tuned loop's body from the engine's", tuned_apart / std::max(size, 1e-12f), "of its size (largest)", 4}});
    }
    return report;
}

} // namespace

const BenchSuite k_bench_sim{"sim", "Stage A milliseconds per frame, per stage (median of frames)", command_spec, measure};

} // namespace pbdsplat::cli
