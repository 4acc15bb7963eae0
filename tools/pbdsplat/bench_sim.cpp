#include <cstdio>

#include <nlohmann/json.hpp>

#include "core/timer.h"
#include "mesh/mesh_spec.h"
#include "pbdsplat/args.h"
#include "pbdsplat/commands.h"
#include "pbdsplat/sim_baseline.h"
#include "sim/solver.h"
#include "splat/gaussian_record.h"

namespace pbdsplat::cli {

int bench_sim(const std::vector<std::string>& argv) {
    static constexpr const char* help =
        "usage: pbdsplat bench sim [--mesh SPEC] [--pin top|none] [--mode paper|xpbd] [--iterations I]\n"
        "                          [--substeps S] [--frames N] [--warmup K] [--volume on|off] [--threads T]\n"
        "                          [--baseline] [--json]\n"
        "\n"
        "Runs Stage A (the CPU PBD frame of the paper) on a body hanging under gravity\n"
        "and prints the median milliseconds per frame, in total and per stage as the paper's\n"
        "Tables 3 and 4 break them down: apply forces, constraint projection, integrate + normals,\n"
        "and update particles (the particle-to-Gaussian mapping).\n"
        "\n"
        "  --mesh SPEC         icosphere:L, uvsphere:R:S, torus:S:T, box:D, capsule:R:S, grid:N, or\n"
        "                      an OBJ file or model name (teapot.obj); default icosphere:5\n"
        "  --pin top|none      pin the highest particle (default top)\n"
        "  --mode paper|xpbd   solver (default paper: PBD)\n"
        "  --iterations I      constraint iterations per step (default 5)\n"
        "  --substeps S        steps per frame (default 1)\n"
        "  --frames N          measured frames at 60 Hz (default 300)\n"
        "  --warmup K          unmeasured frames first (default 30)\n"
        "  --volume on|off     project the volume constraint (default on)\n"
        "  --threads T         worker threads, the caller included (default 1)\n"
        "  --baseline          also run a minimal hand-written loop of the same workload (PBD, one\n"
        "                      thread, distance constraints in edge order, one volume constraint;\n"
        "                      tools/pbdsplat/sim_baseline.h), frame for frame alternated with the\n"
        "                      engine, and print the ratio of the engine's step to it (paper mode)\n"
        "  --json              print one JSON object on stdout\n";
    auto args = Args::parse(argv, {"json", "help", "baseline"},
                            {"mesh", "pin", "mode", "iterations", "substeps", "frames", "warmup", "volume", "threads"});
    if (!args.ok()) return usage_error("bench sim", args.error().to_string());
    if (args->has("help")) return std::fputs(help, stdout), 0;
    auto iterations = args->get_uint("iterations", 5, 1, 1000);
    auto substeps = args->get_uint("substeps", 1, 1, 1000);
    auto frames = args->get_uint("frames", 300, 1, 1000000);
    auto warmup = args->get_uint("warmup", 30, 0, 1000000);
    auto threads = args->get_uint("threads", 1, 1, 64);
    auto pin = args->get_choice("pin", "top", {"top", "none"});
    auto mode = args->get_choice("mode", "paper", {"paper", "xpbd"});
    auto volume = args->get_choice("volume", "on", {"on", "off"});
    if (const core::Error* e = first_error(iterations, substeps, frames, warmup, threads, pin, mode, volume)) return usage_error("bench sim", e->to_string());
    const std::string spec = args->get_or("mesh", "icosphere:5");

    auto repaired = mesh::load_mesh_spec(spec);
    if (!repaired.ok()) return fail("bench sim", repaired.error().to_string());
    sim::SoftBodyDesc desc;
    desc.volume = volume.value() == "on";
    auto made = sim::make_soft_body(std::move(repaired).value().mesh, desc);
    if (!made.ok()) return fail("bench sim", made.error().to_string());
    sim::SoftBody body = std::move(made).value();
    if (pin.value() == "top") body.pin(body.extreme_particle(1));

    sim::SolverSettings settings;
    settings.mode = mode.value() == "xpbd" ? sim::SolverMode::xpbd : sim::SolverMode::paper;
    settings.iterations = iterations.value();
    settings.substeps = substeps.value();
    settings.volume = desc.volume;
    if (auto v = sim::validate(settings); !v.ok()) return usage_error("bench sim", v.error().to_string());
    const bool with_baseline = args->has("baseline");
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

    core::ThreadPool pool(threads.value());
    sim::Solver solver(&pool);
    splat::Appearance look;
    std::vector<splat::GaussianRecord> records;
    std::vector<double> total, forces, constraints, integrate, update;
    for (uint32_t f = 0; f < warmup.value() + frames.value(); ++f) {
        const sim::StageTimings t = solver.step(body, 1.0f / 60.0f, settings, {}, {});
        core::Stopwatch clock;
        splat::map_points(body.particles.x, body.normals, look, records);
        const double up = clock.elapsed_ms();
        if (f < warmup.value()) continue;
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
    if (args->has("json")) {
        const nlohmann::json j = {{"suite", "sim"},
                                  {"mesh", spec},
                                  {"mode", mode.value()},
                                  {"iterations", iterations.value()},
                                  {"substeps", substeps.value()},
                                  {"volume", desc.volume},
                                  {"threads", threads.value()},
                                  {"particles", body.particle_count()},
                                  {"constraints", n_constraints},
                                  {"frames", frames.value()},
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
                    mode.value().c_str(), iterations.value(), substeps.value(), threads.value());
        std::printf("median of %u frames:\n", frames.value());
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
