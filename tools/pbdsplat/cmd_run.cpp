#include <cstdio>

#include <nlohmann/json.hpp>

#include "demo/app.h"
#include "demo/capture_app.h"
#include "scene/model_scene.h"
#include "pbdsplat/commands.h"
#include "pbdsplat/gpu_options.h"
#include "pbdsplat/scene_arg.h"

namespace pbdsplat::cli {

namespace {

// The run's outcome: its error, its validation messages, or its figures (text or --json).
int finish_run(const Options& opt, const std::string& name, const core::Result<demo::DemoReport>& report,
               const demo::WindowRunOptions& o) {
    if (!report.ok()) return fail("run", report.error().to_string());
    const demo::DemoReport& r = report.value();
    if (o.validation && r.validation_messages > 0)
        return fail("run", std::to_string(r.validation_messages) + " validation messages (see above)");
    if (opt.flag("json")) {
        const nlohmann::json j = {{"command", "run"}, {"scene", name}, {"device", r.device},
                                  {"frames", r.frames}, {"median_frame_ms", r.median_frame_ms}, {"fps", r.fps},
                                  {"fps_before_cut", r.fps_before_cut}, {"fps_after_cut", r.fps_after_cut},
                                  {"cuts", r.cuts}, {"tears", r.tears}, {"pieces", r.pieces}, {"particles", r.particles},
                                  {"gaussians", r.gaussians}, {"vsync", o.vsync}, {"screenshot", r.screenshot}};
        std::printf("%s\n", j.dump().c_str());
        return 0;
    }
    std::printf("%llu frames, median %.2f ms (%.1f FPS)", static_cast<unsigned long long>(r.frames), r.median_frame_ms, r.fps);
    if (r.cuts) std::printf("; %.1f FPS before the first cut, %.1f after", r.fps_before_cut, r.fps_after_cut);
    std::printf("\n");
    if (!r.screenshot.empty()) std::printf("screenshot: %s\n", r.screenshot.c_str());
    return 0;
}

// The options every windowed view shares; non-zero: the usage error's exit code.
int read_window_options(const Options& opt, demo::WindowRunOptions& o) {
    o.frames = opt.whole("frames");
    if (opt.given("screenshot-at")) {
        const uint32_t at = opt.whole("screenshot-at");
        if (o.frames && at >= o.frames)
            return usage_error("run", "--screenshot-at " + std::to_string(at) + " is past the last frame (--frames " +
                                          std::to_string(o.frames) + " runs frames 0 to " + std::to_string(o.frames - 1) + ")");
        o.screenshot_at = at;
    }
    o.screenshot_path = opt.text("screenshot");
    o.vsync = !opt.flag("no-vsync");
    o.hud = !opt.flag("no-hud");
    o.validation = opt.flag("validation");
    o.device = opt.text("device");
    return 0;
}

// A trained capture in the window (demo/capture_app.h).
int run_capture(const std::string& file, const Options& opt) {
    for (const char* key : {"script", "save-scene", "threads"})
        if (opt.given(key)) return usage_error("run", std::string("--") + key + " applies to a scene or a model, not to Gaussians");
    demo::CaptureOptions o;
    o.path = file;
    o.up = opt.text("up") == "y" ? splat::PlyUp::y : splat::PlyUp::minus_y;
    if (opt.given("width")) o.width = opt.whole("width");
    if (opt.given("height")) o.height = opt.whole("height");
    if (opt.given("sort")) o.gpu_sort = opt.text("sort") == "gpu";
    if (const int usage = read_window_options(opt, o)) return usage;
    return finish_run(opt, file, demo::run_capture(o), o);
}

} // namespace

int cmd_run(const std::vector<std::string>& argv) {
    static const CommandSpec command{
        "run", "[SCENE.toml | MODEL | GAUSSIANS.ply]",
        "Opens a window and runs the scene (default: the built-in one) live: drag the body with the\n"
        "left button, draw a cut with the right one, H lists the keys. A .ply of Gaussians (a trained\n"
        "capture) is shown as `render` draws it, turning about its centre until the mouse orbits,\n"
        "pans or zooms. Needs a display; without one, use 'pbdsplat render' (or run under Xvfb:\n"
        "xvfb-run -a pbdsplat run ...).\n",
        with_gpu({whole("frames", "N", 0, 0, 100000000, "end by itself after N frames (0: when the window closes)"),
                  whole("screenshot-at", "K", 0, 0, 100000000, "save frame K (0-based) to --screenshot").default_from("none"),
                  text("screenshot", "FILE.png", demo::k_default_screenshot_path, "where --screenshot-at saves"),
                  text("script", "FILE", "", "scripted input: drags, cuts, keys at frames (see scenes/README.md)")
                      .default_from("none"),
                  flag("no-vsync", "present as fast as frames come (vsync is on by default)"),
                  flag("no-hud", "no text overlay"),
                  choice("up", {"-y", "y"}, "-y", ".ply only: which way is up in the file (-y: 3DGS's convention)"),
                  choice("sort", {"cpu", "gpu"}, "cpu", ".ply only: where the Gaussians are ordered far to near")
                      .default_from("gpu on a GPU, cpu on a CPU device"),
                  whole("width", "W", 0, 16, 16384, "the window and image width").default_from("the scene's"),
                  whole("height", "H", 0, 16, 16384, "the window and image height").default_from("the scene's"),
                  whole("threads", "T", 0, 1, 64, "simulation threads (the result is the same for any count)")
                      .default_from("half the cores, 1 to 8"),
                  save_scene_option(), json_option("at the end, one JSON object: frames, FPS (before and after a cut)")})};
    const Parsed parsed = parse_command(command, argv);
    if (!parsed.options) return parsed.exit_code;
    const Options& opt = *parsed.options;
    const auto& operands = opt.operands();
    if (operands.size() == 1) {
        auto kind = scene::input_kind(operands[0]);
        if (!kind.ok()) return fail("run", kind.error().to_string());
        if (kind.value() == scene::InputKind::gaussians) return run_capture(operands[0], opt);
    }
    for (const char* key : {"up", "sort"})
        if (opt.given(key)) return usage_error("run", std::string("--") + key + " applies to a .ply of Gaussians");
    auto scene = load_scene_arg(opt);
    if (!scene.ok()) return fail("run", scene.error().to_string());
    demo::DemoOptions o;
    o.scene = std::move(scene).value();
    if (opt.given("width")) o.scene.render.width = opt.whole("width");
    if (opt.given("height")) o.scene.render.height = opt.whole("height");
    o.script_path = opt.text("script");
    o.threads = opt.given("threads") ? opt.whole("threads") : demo::default_simulation_threads();
    if (const int usage = read_window_options(opt, o)) return usage;

    return finish_run(opt, o.scene.name, demo::run_demo(o), o);
}

} // namespace pbdsplat::cli
