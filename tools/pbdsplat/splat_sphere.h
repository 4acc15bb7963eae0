#pragma once
// The splat benchmarks' test object: N splats on a unit sphere (a Fibonacci lattice), sized to
// close the surface, seen so that it fills about a third of the image.
#include <vector>

#include "render/frame_inputs.h"
#include "splat/gaussian_record.h"

namespace pbdsplat::cli {

struct SplatSphere {
    std::vector<splat::GaussianRecord> records;
    render::FrameInputs frame;
};

SplatSphere make_splat_sphere(uint32_t count);

} // namespace pbdsplat::cli
