#pragma once
// A .ply of Gaussians as a static scene: how `pbdsplat render file.ply` (and its tests) draw
// one. Files trained elsewhere hold soft, sorted Gaussians whose colour is radiance, so they
// are drawn so: the Gaussian footprint, far to near, unlit, anisotropic and view-dependent
// where the file says.
#include "render/environment.h"
#include "render/splat_renderer.h"
#include "splat/ply.h"

namespace pbdsplat::scene {

// The camera looks at the Gaussians' bounds from the front; lighting leaves colours as stored,
// or, `lit`, shades them as a scene's defaults do (key light, environment map about the
// Gaussians' centre) with their normals: a relit look at a capture, or a check of its normals.
render::FrameInputs ply_view(std::span<const splat::GaussianRecord> records, bool lit = false);

// Renderer options that draw `file` as it was trained (at most `file.records.size()` splats);
// `gpu_sort`: ordered far to near on the device (frame.style.order = gpu), not with sort_ply.
render::RendererOptions ply_renderer_options(const splat::PlyGaussians& file, uint32_t width, uint32_t height, bool gpu_sort = false);

// Where a capture is best sorted on `device_type` (gpu::DeviceCaps::type): its own compute
// passes on a GPU; on a CPU device (Lavapipe) those run on the same cores as the CPU sort, which
// was measured faster there (docs/BENCHMARKS.md, "Captures").
bool ply_sort_on_gpu(const std::string& device_type);

// Sorts the file's streams far to near for the frame's camera.
void sort_ply(splat::PlyGaussians& file, const render::FrameInputs& frame);
// Orders the file far to near for `frame`: on the device (the frame asks for the renderer's
// sort, created with ply_renderer_options(..., gpu_sort)), or here with sort_ply.
void order_ply(splat::PlyGaussians& file, render::FrameInputs& frame, bool gpu_sort);

// Replaces each record's base colour by its lit colour as `frame` shades it (render/cpu_shading.h,
// seen from the frame's eye, `map` the scene's environment): for export to viewers without the
// paper's lighting.
void bake_shading(const render::FrameInputs& frame, const render::EnvironmentMap& map, std::span<splat::GaussianRecord> records);

} // namespace pbdsplat::scene
