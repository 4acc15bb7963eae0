#pragma once
// The interactive demo: a scene running live in a window, driven by the mouse and keys (or an
// input script), with a HUD of the paper's per-stage timings.
#include <optional>
#include <string>

#include "scene/scene.h"

namespace pbdsplat::demo {

inline constexpr const char* k_default_screenshot_path = "pbdsplat-screenshot.png";

// What every windowed view takes: how long it runs, what it saves, how it presents.
struct WindowRunOptions {
    uint64_t frames = 0;                   // 0: until the window closes
    std::optional<uint64_t> screenshot_at; // frame index (0-based) to save
    std::string screenshot_path = k_default_screenshot_path;
    bool vsync = true;
    bool validation = false;
    std::string device;                    // name filter
    bool hud = true;
};

struct DemoOptions : WindowRunOptions {
    scene::Scene scene;
    std::string script_path;               // input script (demo/script.h)
    unsigned threads = 1;                  // simulation threads (the result does not depend on it)
};
// Half the cores, 1 to 8: the other half draw (Lavapipe rasterises on them) or feed the GPU.
unsigned default_simulation_threads();

struct DemoReport {
    uint64_t frames = 0;
    double median_frame_ms = 0.0, fps = 0.0;
    double fps_before_cut = 0.0, fps_after_cut = 0.0;  // 0 when the run had no such frames
    size_t cuts = 0, tears = 0, particles = 0, gaussians = 0;
    size_t pieces = 0;  // connected components of the body at the end
    size_t validation_messages = 0;
    std::string device;
    std::string screenshot;  // the path written, if any
};

// Runs until the window closes or `frames` have run. Errors: no display, no device, a bad
// script, a failed frame; each says what is wrong.
core::Result<DemoReport> run_demo(const DemoOptions& options);

} // namespace pbdsplat::demo
