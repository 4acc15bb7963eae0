#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "core/timer.h"
#include "pbdsplat/commands.h"
#include "pbdsplat/gpu_options.h"
#include "pbdsplat/progress.h"
#include "pbdsplat/scene_arg.h"
#include "scene/scene_runtime.h"

namespace pbdsplat::cli {

int bench_scene(const std::vector<std::string>& argv) {
    static const CommandSpec command{
        "bench scene", "[SCENE.toml]",
        "Runs a scene (default: the built-in one) through its frame graph without writing images and\n"
        "prints the median milliseconds per frame of each stage group and of the whole frame, and the\n"
        "GPU time of each GPU pass from timestamps (the paper's \"GPU Scene\" row).\n",
        with_gpu({whole("frames", "N", 240, 1, 1000000, "frames"), whole("threads", "T", 1, 1, 64, "simulation threads"),
                  flag("passes", "also the median CPU ms of every pass that runs (what culling a pass saves)"),
                  flag("before-after", "also the medians before and after the first cut or tear, and the change\n"
                                       "(the paper's Tables 2-4); without --frames it runs until 3 s\n"
                                       "(simulated) after the first one, and fails if none comes within\n"
                                       "10,000 frames"),
                  json_option()})};
    const Parsed parsed = parse_command(command, argv);
    if (!parsed.options) return parsed.exit_code;
    const Options& opt = *parsed.options;
    const uint32_t frames = opt.whole("frames"), threads = opt.whole("threads");
    const bool before_after = opt.flag("before-after");
    const bool until_after = before_after && !opt.given("frames");  // run until enough frames follow the change
    auto scene = load_scene_arg(opt.operands());
    if (!scene.ok()) return fail("bench scene", scene.error().to_string());
    auto ctx = open_context(opt);
    if (!ctx.ok()) return fail("bench scene", ctx.error().to_string());
    scene::RuntimeOptions options;
    options.gpu = ctx.value().get();
    options.readback = false;
    options.threads = threads;
    auto runtime = scene::SceneRuntime::create(scene.value(), options);
    if (!runtime.ok()) return fail("bench scene", runtime.error().to_string());

    std::vector<double> events, forces, constraints, integrate, update, gpu_record, frame, gpu_upload, gpu_sort, gpu_draw;
    // The paper's rows, split at the first topology change: CPU frame (the CPU stages), GPU
    // scene (the GPU passes), and the four update stages.
    struct Split {
        std::vector<double> cpu_frame, gpu_scene, apply, constraints, integrate, update;
        size_t particles = 0, gaussians = 0, frames = 0;
    } before, after;
    std::vector<std::vector<double>> per_pass;  // per kept pass, per frame
    const uint32_t frames_after = uint32_t(std::ceil(3.0f / std::max(scene->simulation.dt, 1e-6f)));
    constexpr uint32_t k_max_frames = 10000;
    Progress progress("bench scene", until_after ? 0 : frames);
    uint32_t run = 0;
    // Frames after the first change, split by whether this frame changed the topology: what a
    // tear or cut costs above the frames around it.
    std::vector<double> changing_cpu, steady_cpu;
    std::vector<std::vector<double>> changing_pass;  // per kept pass, on the frames that changed
    size_t changes_so_far = 0;
    for (uint32_t f = 0; until_after ? (after.frames < frames_after && f < k_max_frames) : f < frames; ++f) {
        ++run;
        if (auto s = runtime.value()->step(); !s.ok()) return fail("bench scene", s.error().to_string());
        const auto& s = runtime.value()->stats();
        events.push_back(s.events_ms), forces.push_back(s.apply_forces_ms), constraints.push_back(s.constraints_ms);
        integrate.push_back(s.integrate_normals_ms), update.push_back(s.update_particles_ms);
        gpu_record.push_back(s.gpu_record_ms), frame.push_back(s.graph_ms);
        gpu_upload.push_back(s.gpu_upload_ms), gpu_sort.push_back(s.gpu_sort_ms), gpu_draw.push_back(s.gpu_draw_ms);
        const auto& pm = runtime.value()->pass_ms();
        if (per_pass.size() < pm.size()) per_pass.resize(pm.size());
        for (size_t k = 0; k < pm.size(); ++k) per_pass[k].push_back(pm[k]);
        Split& part = s.cuts + s.tears == 0 ? before : after;
        // The events group holds the topology pass (cuts, tears and their follow-up): adding
        // topology_ms as well counted it twice.
        part.cpu_frame.push_back(s.events_ms + s.apply_forces_ms + s.constraints_ms + s.integrate_normals_ms +
                                 s.update_particles_ms + s.gpu_record_ms);
        part.gpu_scene.push_back(s.gpu_scene_ms());
        if (&part == &after) (s.cuts + s.tears > changes_so_far ? changing_cpu : steady_cpu).push_back(part.cpu_frame.back());
        if (s.cuts + s.tears > changes_so_far) {
            if (changing_pass.size() < pm.size()) changing_pass.resize(pm.size());
            for (size_t k = 0; k < pm.size(); ++k) changing_pass[k].push_back(pm[k]);
        }
        changes_so_far = s.cuts + s.tears;
        part.apply.push_back(s.apply_forces_ms), part.constraints.push_back(s.constraints_ms);
        part.integrate.push_back(s.integrate_normals_ms), part.update.push_back(s.update_particles_ms);
        part.particles = s.particles, part.gaussians = s.gaussians, ++part.frames;
        progress.frame_done(run);
    }
    if (before_after && (before.frames == 0 || after.frames == 0))
        return fail("bench scene", scene->name + ": no frames " + std::string(before.frames == 0 ? "before" : "after") +
                                       " the first cut or tear in " + std::to_string(run) + " frames" +
                                       (until_after ? " (the scene has none)" : "; run longer (--frames) or leave --frames out"));
    if (auto v = check_validation(*ctx.value()); !v.ok()) return fail("bench scene", v.error().to_string());
    size_t kept = 0, total = 0;
    for (const auto& p : runtime.value()->graph().describe()) ++total, kept += p.culled ? 0 : 1;
    const auto& s = runtime.value()->stats();
    if (opt.flag("json")) {
        const nlohmann::json j = {{"suite", "scene"},
                                  {"scene", scene->name},
                                  {"frames", run},
                                  {"particles", s.particles},
                                  {"passes", total},
                                  {"passes_run", kept},
                                  {"median_ms", core::median(frame)},
                                  {"stages_median_ms", {{"events", core::median(events)},
                                                        {"apply_forces", core::median(forces)},
                                                        {"constraint_projection", core::median(constraints)},
                                                        {"integrate_normals", core::median(integrate)},
                                                        {"update_particles", core::median(update)},
                                                        {"gpu_record", core::median(gpu_record)}}},
                                  {"gpu_median_ms", {{"upload", core::median(gpu_upload)},
                                                     {"sort", core::median(gpu_sort)},
                                                     {"draw", core::median(gpu_draw)}}},
                                  {"gpu_timestamps", ctx.value()->caps().timestamps}};
        nlohmann::json out = j;
        if (opt.flag("passes")) {
            out["passes_median_ms"] = nlohmann::json::object();
            size_t k = 0;
            for (const auto& p : runtime.value()->graph().describe())
                if (!p.culled && k < per_pass.size()) out["passes_median_ms"][p.name] = core::median(per_pass[k++]);
        }
        if (opt.flag("before-after"))
            for (const auto& [name, part] : {std::pair<const char*, const Split*>{"before", &before}, {"after", &after}})
                out[name] = {{"frames", part->frames}, {"particles", part->particles}, {"gaussians", part->gaussians},
                             {"cpu_frame_ms", core::median(part->cpu_frame)}, {"gpu_scene_ms", core::median(part->gpu_scene)},
                             {"apply_forces_ms", core::median(part->apply)}, {"constraint_projection_ms", core::median(part->constraints)},
                             {"integrate_normals_ms", core::median(part->integrate)}, {"update_particles_ms", core::median(part->update)}};
        if (opt.flag("before-after"))
            out["change_frames"] = {{"frames", changing_cpu.size()}, {"cpu_frame_ms", core::median(changing_cpu)},
                                    {"steady_frames", steady_cpu.size()}, {"steady_cpu_frame_ms", core::median(steady_cpu)}};
        std::printf("%s\n", out.dump().c_str());
    } else {
        std::printf("scene %s: %zu particles, %zu of %zu passes run, median of %u frames:\n", scene->name.c_str(),
                    s.particles, kept, total, run);
        std::printf("  events                 %8.3f ms\n  apply forces           %8.3f ms\n  constraint projection  %8.3f ms\n"
                    "  integrate + normals    %8.3f ms\n  update particles       %8.3f ms\n  GPU recording          %8.3f ms\n"
                    "  frame (wall)           %8.3f ms (waits for the GPU when it is the bottleneck)\n",
                    core::median(events), core::median(forces), core::median(constraints), core::median(integrate),
                    core::median(update), core::median(gpu_record), core::median(frame));
        if (ctx.value()->caps().timestamps)
            std::printf("GPU Scene (timestamps):\n  upload                 %8.3f ms\n  sort                   %8.3f ms\n"
                        "  splat pass             %8.3f ms\n",
                        core::median(gpu_upload), core::median(gpu_sort), core::median(gpu_draw));
        else
            std::printf("GPU Scene: device '%s' has no timestamp queries\n", ctx.value()->caps().name.c_str());
        if (opt.flag("passes")) {
            std::printf("per pass (median CPU ms; GPU passes: recording%s):\n",
                        changing_pass.empty() ? "" : "; then the median on the frames that cut or tore");
            size_t k = 0;
            for (const auto& p : runtime.value()->graph().describe()) {
                if (p.culled) {
                    std::printf("  %-22s culled: %s\n", p.name.c_str(), p.reason.c_str());
                } else if (k < per_pass.size()) {
                    std::printf("  %-22s %9.4f", p.name.c_str(), core::median(per_pass[k]));
                    if (k < changing_pass.size()) std::printf(" %9.4f", core::median(changing_pass[k]));
                    std::printf("\n");
                    ++k;
                }
            }
        }
        if (opt.flag("before-after")) {
            if (after.frames == 0 || before.frames == 0) {
                std::printf("before/after: the run has no frames on one side of a cut or tear\n");
            } else {
                std::printf("before and after the first cut or tear (%zu -> %zu particles, %zu -> %zu Gaussians; medians, ms):\n",
                            before.particles, after.particles, before.gaussians, after.gaussians);
                auto row = [](const char* name, const std::vector<double>& b, const std::vector<double>& a) {
                    const double mb = core::median(b), ma = core::median(a);
                    std::printf("  %-28s %9.3f %9.3f %+9.3f %+8.2f%%\n", name, mb, ma, ma - mb, mb > 0 ? 100.0 * (ma - mb) / mb : 0.0);
                };
                std::printf("  %-28s %9s %9s %9s %9s\n", "", "before", "after", "delta", "delta %");
                row("CPU frame", before.cpu_frame, after.cpu_frame);
                row("GPU scene", before.gpu_scene, after.gpu_scene);
                row("apply forces", before.apply, after.apply);
                row("constraint projection", before.constraints, after.constraints);
                row("integrate + normals", before.integrate, after.integrate);
                row("update particles", before.update, after.update);
                if (!changing_cpu.empty())
                    std::printf("  frames that cut or tore: %zu, CPU frame %.3f ms against %.3f ms on the %zu after without (%+.3f)\n",
                                changing_cpu.size(), core::median(changing_cpu), core::median(steady_cpu), steady_cpu.size(),
                                core::median(changing_cpu) - core::median(steady_cpu));
            }
        }
    }
    return 0;
}

} // namespace pbdsplat::cli
