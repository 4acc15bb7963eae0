#include <cstdio>

#include <nlohmann/json.hpp>

#include "demo/app.h"
#include "pbdsplat/commands.h"
#include "pbdsplat/gpu_options.h"
#include "pbdsplat/scene_arg.h"

namespace pbdsplat::cli {

int cmd_run(const std::vector<std::string>& argv) {
    static constexpr const char* help =
        "usage: pbdsplat run [SCENE.toml] [--frames N] [--screenshot-at K] [--screenshot FILE.png]\n"
        "                    [--script FILE] [--no-vsync] [--no-hud] [--width W] [--height H] [--json]\n"
        "                    [--validation] [--device NAME]\n"
        "\n"
        "Opens a window and runs the scene (default: the built-in one) live: drag the body with the\n"
        "left button, draw a cut with the right one, H lists the keys. Needs a display; without one,\n"
        "use 'pbdsplat render' (or run under Xvfb: xvfb-run -a pbdsplat run ...).\n"
        "\n"
        "  --frames N          end by itself after N frames (default: when the window closes)\n"
        "  --screenshot-at K   save frame K (0-based) to --screenshot (default pbdsplat-screenshot.png)\n"
        "  --script FILE       scripted input: drags, cuts, keys at frames (see scenes/README.md)\n"
        "  --no-vsync          present as fast as frames come (vsync is on by default)\n"
        "  --no-hud            no text overlay\n"
        "  --width W, --height H   the window and image size (default: the scene's)\n"
        "  --json              at the end, one JSON object: frames, FPS (before and after a cut)\n";
    std::set<std::string> flags = k_gpu_flags;
    flags.insert({"help", "json", "no-vsync", "no-hud"});
    std::set<std::string> valued = k_gpu_options;
    valued.insert({"frames", "screenshot-at", "screenshot", "script", "width", "height"});
    auto args = Args::parse(argv, flags, valued);
    if (!args.ok()) return usage_error("run", args.error().to_string());
    if (args->has("help")) return std::fputs(help, stdout), 0;
    auto frames = args->get_uint("frames", 0, 0, 100000000);
    if (!frames.ok()) return usage_error("run", frames.error().to_string());
    auto scene = load_scene_arg(args->positionals());
    if (!scene.ok()) return fail("run", scene.error().to_string());
    demo::DemoOptions o;
    o.scene = std::move(scene).value();
    auto width = args->get_uint("width", o.scene.render.width, 16, 16384);
    auto height = args->get_uint("height", o.scene.render.height, 16, 16384);
    if (!width.ok()) return usage_error("run", width.error().to_string());
    if (!height.ok()) return usage_error("run", height.error().to_string());
    o.scene.render.width = width.value();
    o.scene.render.height = height.value();
    o.frames = frames.value();
    if (args->has("screenshot-at")) {
        auto at = args->get_uint("screenshot-at", 0, 0, 100000000);
        if (!at.ok()) return usage_error("run", at.error().to_string());
        if (o.frames && at.value() >= o.frames)
            return usage_error("run", "--screenshot-at " + std::to_string(at.value()) + " is past the last frame (--frames " +
                                          std::to_string(o.frames) + " runs frames 0 to " + std::to_string(o.frames - 1) + ")");
        o.screenshot_at = at.value();
    }
    o.screenshot_path = args->get_or("screenshot", o.screenshot_path);
    o.script_path = args->get_or("script", "");
    o.vsync = !args->has("no-vsync");
    o.hud = !args->has("no-hud");
    o.validation = args->has("validation");
    o.device = args->get_or("device", "");

    auto report = demo::run_demo(o);
    if (!report.ok()) return fail("run", report.error().to_string());
    const demo::DemoReport& r = report.value();
    if (o.validation && r.validation_messages > 0)
        return fail("run", std::to_string(r.validation_messages) + " validation messages (see above)");
    if (args->has("json")) {
        const nlohmann::json j = {{"command", "run"}, {"scene", o.scene.name}, {"device", r.device},
                                  {"frames", r.frames}, {"median_frame_ms", r.median_frame_ms}, {"fps", r.fps},
                                  {"fps_before_cut", r.fps_before_cut}, {"fps_after_cut", r.fps_after_cut},
                                  {"cuts", r.cuts}, {"tears", r.tears}, {"pieces", r.pieces}, {"particles", r.particles},
                                  {"gaussians", r.gaussians}, {"vsync", o.vsync}, {"screenshot", r.screenshot}};
        std::printf("%s\n", j.dump().c_str());
    } else {
        std::printf("%llu frames, median %.2f ms (%.1f FPS)", static_cast<unsigned long long>(r.frames), r.median_frame_ms, r.fps);
        if (r.cuts) std::printf("; %.1f FPS before the first cut, %.1f after", r.fps_before_cut, r.fps_after_cut);
        std::printf("\n");
        if (!r.screenshot.empty()) std::printf("screenshot: %s\n", r.screenshot.c_str());
    }
    return 0;
}

} // namespace pbdsplat::cli
