#pragma once
// One frame of the mesh raster pass through a small frame graph (raster, then readback;
// barriers derived): the coverage reference, the lit mesh the paper compares against, and its
// benchmark.
#include "core/image.h"
#include "render/mesh_raster.h"

namespace pbdsplat::passes {

struct MeshImage {
    core::ImageRgba8 image;
    double gpu_ms = 0.0;  // the raster pass, from timestamps (0 where the device has none)
};

core::Result<MeshImage> render_mesh_image(gpu::Context& ctx, render::MeshRaster& raster, const render::FrameInputs& frame,
                                          render::MeshView view, const Vec3f& albedo = Vec3f(0.8f, 0.2f, 0.2f));

} // namespace pbdsplat::passes
