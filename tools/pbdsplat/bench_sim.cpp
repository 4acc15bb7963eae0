#include <cstdio>

#include <nlohmann/json.hpp>

#include "core/timer.h"
#include "mesh/mesh_spec.h"
#include "pbdsplat/options.h"
#include "pbdsplat/commands.h"
#include "pbdsplat/sim_baseline.h"
#include "sim/solver.h"
#include "splat/gaussian_record.h"

namespace pbdsplat::cli {

int bench_sim(const std::vector<std::string>& argv) {
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
         flag("baseline", "also run a minimal hand-written loop of the same workload (PBD, one\n"
                          "thread, distance constraints in edge order, one volume constraint;\n"
                          "tools/pbdsplat/sim_baseline.h), frame for frame alternated with the\n"
                          "engine, and print the ratio of the engine's step to it (paper mode)"),
         json_option()}};
    const Parsed parsed = parse_command(command, argv);
    if (!parsed.options) return parsed.exit_code;
    const Options& opt = *parsed.options;
    const uint32_t iterations = opt.whole("iterations"), substeps = opt.whole("substeps"), frames = opt.whole("frames");
    const uint32_t warmup = opt.whole("warmup"), threads = opt.whole("threads");
    const std::string& spec = opt.text("mesh");

    auto repaired = mesh::load_mesh_spec(spec);
    if (!repaired.ok()) return fail("bench sim", repaired.error().to_string());
    sim::SoftBodyDesc desc;
    desc.volume = opt.text("volume") == "on";
    auto made = sim::make_soft_body(std::move(repaired).value().mesh, desc);
    if (!made.ok()) return fail("bench sim", made.error().to_string());
    sim::SoftBody body = std::move(made).value();
    if (opt.text("pin") == "top") body.pin(body.extreme_particle(1));

    sim::SolverSettings settings;
    settings.mode = opt.named<sim::SolverMode>("mode", sim::k_solver_mode_names);
    settings.iterations = iterations;
    settings.substeps = substeps;
    settings.volume = desc.volume;
    if (auto v = sim::validate(settings); !v.ok()) return usage_error("bench sim", v.error().to_string());
    const bool with_baseline = opt.flag("baseline");
    if (with_baseline && settings.mode != sim::SolverMode::paper) return usage_error("bench sim", "--baseline runs PBD: use --mode paper");
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
    std::vector<double> engine_step, baseline_step;

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
            // Alternated frame for frame, so the machine's drift falls on both alike.
            const core::Stopwatch base_clock;
            for (uint32_t k = 0; k < settings.substeps; ++k) baseline.step(1.0f / 60.0f / float(settings.substeps));
            baseline_step.push_back(base_clock.elapsed_ms());
        }
        engine_step.push_back(t.total());
        total.push_back(t.total() + up);
        forces.push_back(t.apply_forces);
        constraints.push_back(t.constraints);
        integrate.push_back(t.integrate_normals);
        update.push_back(up);
    }
    for (const auto& x : body.particles.x)
        if (!x.allFinite()) return fail("bench sim", "the simulation produced NaN or Inf; the settings are unstable");

    const size_t n_constraints = body.distance.size() + (settings.volume ? body.volumes.size() : 0);
    if (opt.flag("json")) {
        const nlohmann::json j = {{"suite", "sim"},
                                  {"mesh", spec},
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
                                                        {"update_particles", core::median(update)}}}};
        nlohmann::json out = j;
        if (with_baseline)
            out["baseline"] = {{"engine_step_median_ms", core::median(engine_step)}, {"baseline_median_ms", core::median(baseline_step)},
                               {"ratio", core::median(engine_step) / std::max(1e-9, core::median(baseline_step))}};
        std::printf("%s\n", out.dump().c_str());
    } else {
        std::printf("%s: %zu particles, %zu distance + %zu volume constraints; %s, I=%u, S=%u, %u thread(s)\n",
                    spec.c_str(), body.particle_count(), body.distance.size(), settings.volume ? body.volumes.size() : 0,
                    opt.text("mode").c_str(), iterations, substeps, threads);
        std::printf("median of %u frames:\n", frames);
        std::printf("  apply forces           %8.3f ms\n", core::median(forces));
        std::printf("  constraint projection  %8.3f ms\n", core::median(constraints));
        std::printf("  integrate + normals    %8.3f ms\n", core::median(integrate));
        std::printf("  update particles       %8.3f ms (particle-to-Gaussian mapping)\n", core::median(update));
        std::printf("  Stage A frame          %8.3f ms\n", core::median(total));
        if (with_baseline)
            std::printf("baseline (minimal loop, same workload, alternated): engine step %.3f ms, loop %.3f ms, ratio %.2f\n",
                        core::median(engine_step), core::median(baseline_step),
                        core::median(engine_step) / std::max(1e-9, core::median(baseline_step)));
    }
    return 0;
}

} // namespace pbdsplat::cli
