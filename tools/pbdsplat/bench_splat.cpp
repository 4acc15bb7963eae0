#include <cmath>

#include "core/timer.h"
#include "pbdsplat/bench_suites.h"
#include "pbdsplat/progress.h"
#include "pbdsplat/gpu_options.h"
#include "pbdsplat/splat_sphere.h"
#include "pbdsplat/upload_path_arg.h"
#include "passes/offscreen_renderer.h"

namespace pbdsplat::cli {

namespace {

const CommandSpec& command_spec() {
    static const CommandSpec command{
        "bench splat", "",
        "Renders N splats spread over a sphere R times (after K unmeasured frames), every frame\n"
        "uploading all records and reading the image back, and prints the median time of each\n"
        "stage: the CPU writing the records, and the GPU stages from timestamp queries, plus the\n"
        "median CPU wall time of a whole frame.\n",
        with_gpu({whole("count", "N", 20000, 1, 1u << 24, "splats"),
                  whole("width", "W", 1280, 1, 16384, "target width"),
                  whole("height", "H", 720, 1, 16384, "target height"),
                  whole("repeat", "R", 30, 1, 100000, "measured frames"),
                  whole("warmup", "K", 5, 0, 100000, "unmeasured frames first"), upload_option(), json_option()})};
    return command;
}

Outcome measure(const Options& opt) {
    const uint32_t count = opt.whole("count"), width = opt.whole("width"), height = opt.whole("height");
    const uint32_t repeat = opt.whole("repeat"), warmup = opt.whole("warmup");
    const std::optional<gpu::UploadPath> upload = upload_path(opt);

    auto ctx = open_context(opt);
    if (!ctx.ok()) return ctx.error();
    if (!ctx.value()->caps().timestamps)
        return core::make_error("device '" + ctx.value()->caps().name + "' has no timestamp queries to measure with");

    auto [records, frame] = make_splat_sphere(count);
    render::RendererOptions options;
    options.width = width;
    options.height = height;
    options.max_splats = count;
    options.frames_in_flight = 1;  // one frame at a time, so each frame's stages are timed alone
    options.upload_path = upload;
    auto renderer = passes::OffscreenRenderer::create(*ctx.value(), options);
    if (!renderer.ok()) return renderer.error();

    std::vector<double> up_cpu, up, draw, back, wall;
    Progress progress("bench splat", warmup + repeat);
    for (uint32_t i = 0; i < warmup + repeat; ++i) {
        if (i > 0) progress.frame_done(i);
        core::Stopwatch sw;
        PBDSPLAT_TRY(renderer.value()->render(records, frame));
        PBDSPLAT_TRY(renderer.value()->finish());
        const double ms = sw.elapsed_ms();
        if (i < warmup) continue;
        const render::GpuTimings t = renderer.value()->timings();
        up_cpu.push_back(t.upload_cpu_ms), up.push_back(t.upload_ms), draw.push_back(t.draw_ms), back.push_back(t.readback_ms), wall.push_back(ms);
    }
    PBDSPLAT_TRY(check_validation(*ctx.value()));

    const char* path = gpu::upload_path_name(renderer.value()->upload_path());
    const auto& caps = ctx.value()->caps();
    Report report("splat");
    report.json().update({{"device", caps.name},
                          {"driver", caps.driver},
                          {"count", count},
                          {"width", width},
                          {"height", height},
                          {"repeat", repeat},
                          {"upload_path", path},
                          {"median_ms", {{"upload_cpu", core::median(up_cpu)},
                                         {"upload", core::median(up)},
                                         {"draw", core::median(draw)},
                                         {"readback", core::median(back)},
                                         {"frame_wall", core::median(wall)}}}});
    report.line(format("device %s (%s)", caps.name.c_str(), caps.driver.c_str()));
    report.figures(format("%u splats at %ux%u, %s uploads, median of %u frames:", count, width, height, path, repeat),
                   {{"upload (writing records)", core::median(up_cpu), "ms CPU"},
                    {"upload (staging copy)", core::median(up), "ms GPU"},
                    {"draw", core::median(draw), "ms GPU (visibility + colour splat passes)"},
                    {"readback", core::median(back), "ms GPU (image to host buffer)"},
                    {"frame", core::median(wall), "ms CPU wall, from recording to image in hand"}});
    return report;
}

} // namespace

const BenchSuite k_bench_splat{"splat", "GPU milliseconds of upload, draw and readback for N splats (median of repeats)",
                               command_spec, measure};

} // namespace pbdsplat::cli
