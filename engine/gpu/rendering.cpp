#include "gpu/rendering.h"

#include <array>

#include "core/assert.h"

namespace pbdsplat::gpu {

void begin_rendering(VkCommandBuffer cmd, VkExtent2D extent, const ColorTarget& color, const DepthTarget& depth,
                     std::optional<VkRect2D> area) {
    begin_rendering(cmd, extent, std::span<const ColorTarget>(&color, 1), depth, area);
}

void begin_rendering(VkCommandBuffer cmd, VkExtent2D extent, std::span<const ColorTarget> colors, const DepthTarget& depth,
                     std::optional<VkRect2D> area) {
    PBDSPLAT_ASSERT(!colors.empty() && colors.size() <= 4, "begin_rendering: give 1 to 4 colour targets");
    std::array<VkRenderingAttachmentInfo, 4> c{};
    for (size_t i = 0; i < colors.size(); ++i) {
        c[i].sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO;
        c[i].imageView = colors[i].view;
        c[i].imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
        c[i].loadOp = colors[i].load;
        c[i].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
        c[i].clearValue.color = colors[i].clear;
    }
    VkRenderingAttachmentInfo d{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    d.imageView = depth.view;
    d.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
    d.loadOp = depth.load;
    d.storeOp = depth.store;
    d.clearValue.depthStencil = {depth.clear, 0};
    VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
    const VkRect2D rect = area.value_or(VkRect2D{{0, 0}, extent});
    info.renderArea = rect;
    info.layerCount = 1;
    info.colorAttachmentCount = uint32_t(colors.size());
    info.pColorAttachments = c.data();
    info.pDepthAttachment = depth.view ? &d : nullptr;
    vkCmdBeginRendering(cmd, &info);
    const VkViewport viewport{0.0f, 0.0f, float(extent.width), float(extent.height), 0.0f, 1.0f};
    vkCmdSetViewport(cmd, 0, 1, &viewport);
    vkCmdSetScissor(cmd, 0, 1, &rect);
}

} // namespace pbdsplat::gpu
