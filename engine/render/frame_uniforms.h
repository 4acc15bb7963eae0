#pragma once
#include "gpu_types.h"
#include "render/frame_inputs.h"

namespace pbdsplat::render {

// The std140 block every pass reads, from the frame's camera, lights and splat style.
gpu_types::FrameUniforms make_frame_uniforms(const FrameInputs& in, uint32_t width, uint32_t height);

} // namespace pbdsplat::render
