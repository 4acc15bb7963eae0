#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "core/timer.h"
#include "pbdsplat/commands.h"
#include "pbdsplat/progress.h"
#include "pbdsplat/gpu_options.h"
#include "pbdsplat/splat_sphere.h"
#include "pbdsplat/upload_path_arg.h"
#include "passes/offscreen_renderer.h"

namespace pbdsplat::cli {

int bench_splat(const std::vector<std::string>& argv) {
    static constexpr const char* help =
        "usage: pbdsplat bench splat [--count N] [--width W] [--height H] [--repeat R] [--warmup K]\n"
        "                            [--upload auto|staged|direct] [--json] [--validation] [--device NAME]\n"
        "\n"
        "Renders N splats spread over a sphere R times (after K unmeasured frames), every frame\n"
        "uploading all records and reading the image back, and prints the median time of each\n"
        "stage: the CPU writing the records, and the GPU stages from timestamp queries, plus the\n"
        "median CPU wall time of a whole frame.\n"
        "\n"
        "  --count N           splats (default 20000)\n"
        "  --width W, --height H   target size (default 1280x720)\n"
        "  --repeat R          measured frames (default 30)\n"
        "  --warmup K          unmeasured frames first (default 5)\n"
        "  --upload PATH       auto (default), staged or direct\n"
        "  --json              print one JSON object on stdout\n";
    std::set<std::string> flags = k_gpu_flags;
    flags.insert({"json", "help"});
    std::set<std::string> valued = k_gpu_options;
    valued.insert({"count", "width", "height", "repeat", "warmup", "upload"});
    auto args = Args::parse(argv, flags, valued);
    if (!args.ok()) return usage_error("bench splat", args.error().to_string());
    if (args->has("help")) return std::fputs(help, stdout), 0;
    auto count = args->get_uint("count", 20000, 1, 1u << 24);
    auto width = args->get_uint("width", 1280, 1, 16384);
    auto height = args->get_uint("height", 720, 1, 16384);
    auto repeat = args->get_uint("repeat", 30, 1, 100000);
    auto warmup = args->get_uint("warmup", 5, 0, 100000);
    auto upload = parse_upload_path(args->get_or("upload", "auto"));
    for (const core::Error* e :
         {count.ok() ? nullptr : &count.error(), width.ok() ? nullptr : &width.error(),
          height.ok() ? nullptr : &height.error(), repeat.ok() ? nullptr : &repeat.error(),
          warmup.ok() ? nullptr : &warmup.error(), upload.ok() ? nullptr : &upload.error()})
        if (e) return usage_error("bench splat", e->to_string());

    auto ctx = open_context(args.value());
    if (!ctx.ok()) return fail("bench splat", ctx.error().to_string());
    if (!ctx.value()->caps().timestamps)
        return fail("bench splat", "device '" + ctx.value()->caps().name + "' has no timestamp queries to measure with");

    auto [records, frame] = make_splat_sphere(count.value());
    render::RendererOptions options;
    options.width = width.value();
    options.height = height.value();
    options.max_splats = count.value();
    options.frames_in_flight = 1;  // one frame at a time, so each frame's stages are timed alone
    options.upload_path = upload.value();
    auto renderer = passes::OffscreenRenderer::create(*ctx.value(), options);
    if (!renderer.ok()) return fail("bench splat", renderer.error().to_string());

    std::vector<double> up_cpu, up, draw, back, wall;
    Progress progress("bench splat", warmup.value() + repeat.value());
    for (uint32_t i = 0; i < warmup.value() + repeat.value(); ++i) {
        if (i > 0) progress.frame_done(i);
        core::Stopwatch sw;
        if (auto s = renderer.value()->render(records, frame); !s.ok()) return fail("bench splat", s.error().to_string());
        auto img = renderer.value()->finish();
        if (!img.ok()) return fail("bench splat", img.error().to_string());
        const double ms = sw.elapsed_ms();
        if (i < warmup.value()) continue;
        const render::GpuTimings t = renderer.value()->timings();
        up_cpu.push_back(t.upload_cpu_ms), up.push_back(t.upload_ms), draw.push_back(t.draw_ms), back.push_back(t.readback_ms), wall.push_back(ms);
    }
    auto v = check_validation(*ctx.value());
    if (!v.ok()) return fail("bench splat", v.error().to_string());

    const char* path = gpu::upload_path_name(renderer.value()->upload_path());
    const auto& caps = ctx.value()->caps();
    if (args->has("json")) {
        const nlohmann::json j = {{"suite", "splat"},
                                  {"device", caps.name},
                                  {"driver", caps.driver},
                                  {"count", count.value()},
                                  {"width", width.value()},
                                  {"height", height.value()},
                                  {"repeat", repeat.value()},
                                  {"upload_path", path},
                                  {"median_ms", {{"upload_cpu", core::median(up_cpu)},
                                                 {"upload", core::median(up)},
                                                 {"draw", core::median(draw)},
                                                 {"readback", core::median(back)},
                                                 {"frame_wall", core::median(wall)}}}};
        std::printf("%s\n", j.dump().c_str());
    } else {
        std::printf("device %s (%s)\n", caps.name.c_str(), caps.driver.c_str());
        std::printf("%u splats at %ux%u, %s uploads, median of %u frames:\n", count.value(), width.value(),
                    height.value(), path, repeat.value());
        std::printf("  upload    %8.3f ms CPU (writing records) + %.3f ms GPU (staging copy)\n", core::median(up_cpu),
                    core::median(up));
        std::printf("  draw      %8.3f ms GPU (visibility + colour splat passes)\n", core::median(draw));
        std::printf("  readback  %8.3f ms GPU (image to host buffer)\n", core::median(back));
        std::printf("  frame     %8.3f ms CPU wall, from recording to image in hand\n", core::median(wall));
    }
    return 0;
}

} // namespace pbdsplat::cli
