#pragma once
// A trained capture (a 3DGS .ply) in a window: drawn as `render FILE.ply` draws it, turning
// slowly about its centre until the mouse takes the camera (orbit, pan, zoom). Nothing moves
// but the eye, so no simulation runs: each frame is a sort (on the GPU on a GPU) and a draw.
#include <optional>
#include <string>

#include "demo/app.h"
#include "splat/ply.h"

namespace pbdsplat::demo {

struct CaptureOptions : WindowRunOptions {
    std::string path;
    splat::PlyUp up = splat::PlyUp::minus_y;
    uint32_t width = 1280, height = 720;
    std::optional<bool> gpu_sort;  // unset: the device decides (scene::ply_sort_on_gpu)
    float orbit_degrees_per_second = 15.0f;
};

// Errors: an unreadable file, no display, no device; each says what is wrong. The report's
// particles and cuts stay 0; gaussians is the file's count.
core::Result<DemoReport> run_capture(const CaptureOptions& options);

} // namespace pbdsplat::demo
