#pragma once
// The splat benchmarks' test object: N splats on a unit sphere (a Fibonacci lattice), sized to
// close the surface, seen so that it fills about a third of the image.
#include <vector>

#include "gpu/context.h"
#include "render/frame_inputs.h"
#include "splat/gaussian_record.h"

namespace pbdsplat::cli {

struct SplatSphere {
    std::vector<splat::GaussianRecord> records;
    render::FrameInputs frame;
};

SplatSphere make_splat_sphere(uint32_t count);

// The mesh pipeline on the same sphere: a lit icosphere with about `count` vertices (the
// nearest subdivision level), rendered `warmup + repeat` times; the median GPU raster time.
struct MeshRasterFigures {
    size_t vertices = 0, triangles = 0;
    double median_ms = 0.0;
};
core::Result<MeshRasterFigures> bench_mesh_raster(gpu::Context& ctx, uint32_t count, const render::FrameInputs& frame,
                                                  uint32_t width, uint32_t height, uint32_t warmup, uint32_t repeat);

} // namespace pbdsplat::cli
