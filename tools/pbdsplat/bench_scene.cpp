#include <cstdio>

#include <nlohmann/json.hpp>

#include "core/timer.h"
#include "pbdsplat/commands.h"
#include "pbdsplat/gpu_options.h"
#include "pbdsplat/scene_arg.h"
#include "scene/scene_runtime.h"

namespace pbdsplat::cli {

int bench_scene(const std::vector<std::string>& argv) {
    static constexpr const char* help =
        "usage: pbdsplat bench scene [SCENE.toml] [--frames N] [--threads T] [--json] [--validation] [--device NAME]\n"
        "\n"
        "Runs a scene (default: the built-in one) through its frame graph without writing images and\n"
        "prints the median milliseconds per frame of each stage group and of the whole frame, and the\n"
        "GPU time of each GPU pass from timestamps (the paper's \"GPU Scene\" row).\n"
        "\n"
        "  --frames N          frames (default 240)\n"
        "  --threads T         simulation threads (default 1)\n"
        "  --json              print one JSON object on stdout\n";
    std::set<std::string> flags = k_gpu_flags;
    flags.insert({"help", "json"});
    std::set<std::string> valued = k_gpu_options;
    valued.insert({"frames", "threads"});
    auto args = Args::parse(argv, flags, valued);
    if (!args.ok()) return usage_error("bench scene", args.error().to_string());
    if (args->has("help")) return std::fputs(help, stdout), 0;
    auto frames = args->get_uint("frames", 240, 1, 1000000);
    auto threads = args->get_uint("threads", 1, 1, 64);
    if (!frames.ok()) return usage_error("bench scene", frames.error().to_string());
    if (!threads.ok()) return usage_error("bench scene", threads.error().to_string());
    auto scene = load_scene_arg(args->positionals());
    if (!scene.ok()) return fail("bench scene", scene.error().to_string());
    auto ctx = open_context(args.value());
    if (!ctx.ok()) return fail("bench scene", ctx.error().to_string());
    scene::RuntimeOptions options;
    options.gpu = ctx.value().get();
    options.readback = false;
    options.threads = threads.value();
    auto runtime = scene::SceneRuntime::create(scene.value(), options);
    if (!runtime.ok()) return fail("bench scene", runtime.error().to_string());

    std::vector<double> events, forces, constraints, integrate, update, gpu_record, frame, gpu_upload, gpu_sort, gpu_draw;
    for (uint32_t f = 0; f < frames.value(); ++f) {
        if (auto s = runtime.value()->step(); !s.ok()) return fail("bench scene", s.error().to_string());
        const auto& s = runtime.value()->stats();
        events.push_back(s.events_ms), forces.push_back(s.apply_forces_ms), constraints.push_back(s.constraints_ms);
        integrate.push_back(s.integrate_normals_ms), update.push_back(s.update_particles_ms);
        gpu_record.push_back(s.gpu_record_ms), frame.push_back(s.graph_ms);
        gpu_upload.push_back(s.gpu_upload_ms), gpu_sort.push_back(s.gpu_sort_ms), gpu_draw.push_back(s.gpu_draw_ms);
    }
    if (auto v = check_validation(*ctx.value()); !v.ok()) return fail("bench scene", v.error().to_string());
    size_t kept = 0, total = 0;
    for (const auto& p : runtime.value()->graph().describe()) ++total, kept += p.culled ? 0 : 1;
    const auto& s = runtime.value()->stats();
    if (args->has("json")) {
        const nlohmann::json j = {{"suite", "scene"},
                                  {"scene", scene->name},
                                  {"frames", frames.value()},
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
        std::printf("%s\n", j.dump().c_str());
    } else {
        std::printf("scene %s: %zu particles, %zu of %zu passes run, median of %u frames:\n", scene->name.c_str(),
                    s.particles, kept, total, frames.value());
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
    }
    return 0;
}

} // namespace pbdsplat::cli
