#pragma once
// Dynamic rendering into colour attachments and, optionally, a depth attachment, with the
// viewport covering the whole target and the scissor its render area: how every pass here
// begins drawing.
#include <optional>
#include <span>

#include "gpu/vk.h"

namespace pbdsplat::gpu {

struct ColorTarget {
    VkImageView view = VK_NULL_HANDLE;
    VkAttachmentLoadOp load = VK_ATTACHMENT_LOAD_OP_LOAD;
    VkClearColorValue clear{};  // with VK_ATTACHMENT_LOAD_OP_CLEAR
};

struct DepthTarget {
    VkImageView view = VK_NULL_HANDLE;  // none: no depth attachment
    VkAttachmentLoadOp load = VK_ATTACHMENT_LOAD_OP_LOAD;
    VkAttachmentStoreOp store = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    float clear = 1.0f;  // with VK_ATTACHMENT_LOAD_OP_CLEAR
};

// The images must be in COLOR_ATTACHMENT_OPTIMAL and DEPTH_ATTACHMENT_OPTIMAL (the frame
// graph's barriers put them there). The colour is always stored. `area`: the render area and
// scissor (cleared, drawn and stored there alone); the whole extent when left out. The viewport
// is always the whole extent, so the image maps to the target as ever.
void begin_rendering(VkCommandBuffer cmd, VkExtent2D extent, const ColorTarget& color, const DepthTarget& depth = {},
                     std::optional<VkRect2D> area = {});
// Several colour attachments (locations 0, 1, ... in that order; at most 4).
void begin_rendering(VkCommandBuffer cmd, VkExtent2D extent, std::span<const ColorTarget> colors, const DepthTarget& depth = {},
                     std::optional<VkRect2D> area = {});

} // namespace pbdsplat::gpu
