#pragma once
// How well the splats cover the surface they stand for, against a raster of the same deformed
// mesh from the same camera: the hole ratio (share of the mesh's pixels where the splats'
// accumulated alpha stays below 0.5) and the silhouette IoU (splat mask alpha >= 0.5 against
// the mesh mask).
#include <span>

#include "core/image.h"
#include "gpu/context.h"
#include "render/frame_inputs.h"
#include "splat/gaussian_record.h"

namespace pbdsplat::scene {

struct Coverage {
    double hole_ratio = 0.0;
    double silhouette_iou = 0.0;
    size_t mesh_pixels = 0;
    core::ImageRgba8 splats, mesh;  // the two images, for people to look at
};

core::Result<Coverage> measure_coverage(gpu::Context& ctx, std::span<const Vec4f> x,
                                        std::span<const std::array<uint32_t, 3>> triangles,
                                        std::span<const splat::GaussianRecord> records, render::FrameInputs frame,
                                        uint32_t width, uint32_t height);

} // namespace pbdsplat::scene
