#pragma once
// How a GPU operation uses what it touches: the stage and access the frame graph derives
// barriers from, and the layout an image must be in.
#include "gpu/barriers.h"

namespace pbdsplat::render {

struct Use {
    gpu::Access access;
    VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
};

} // namespace pbdsplat::render
