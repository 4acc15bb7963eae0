#pragma once
// Where on screen a frame's splats can reach, so that the passes that work per pixel of the
// splats alone (normalised blending's sums and resolve) clear, draw and resolve that rectangle
// instead of the whole target: a body filling a tenth of the image costs a tenth of the pixels.
#include <cstdint>
#include <span>

#include "core/math.h"
#include "render/frame_inputs.h"
#include "splat/gaussian_record.h"

namespace pbdsplat::render {

// The splats' centres' box and their largest scale (the record's, before the style's
// multiplier); empty when there are none. A non-finite centre draws nothing and is left out.
struct SplatBounds {
    Vec3f lo = Vec3f::Constant(1e30f), hi = Vec3f::Constant(-1e30f);
    float max_scale = 0.0f;
    bool empty() const { return !(lo.x() <= hi.x()); }
};
SplatBounds splat_bounds(std::span<const splat::GaussianRecord> records);

struct PixelRect {
    uint32_t x = 0, y = 0, width = 0, height = 0;
};

// A rectangle of the width x height target holding every pixel the splats can touch under
// `inputs` (camera and style), with a margin: their box grown by half again their reach,
// projected. The whole target where any of it lies behind the near plane or bounds are unknown
// (non-finite); at least one pixel, so a pass always has an area to begin.
PixelRect splat_screen_rect(const SplatBounds& bounds, const FrameInputs& inputs, uint32_t width, uint32_t height);

} // namespace pbdsplat::render
