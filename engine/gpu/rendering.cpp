#include "gpu/rendering.h"

namespace pbdsplat::gpu {

void begin_rendering(VkCommandBuffer cmd, VkExtent2D extent, const ColorTarget& color, const DepthTarget& depth) {
    VkRenderingAttachmentInfo c{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    c.imageView = color.view;
    c.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    c.loadOp = color.load;
    c.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    c.clearValue.color = color.clear;
    VkRenderingAttachmentInfo d{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    d.imageView = depth.view;
    d.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
    d.loadOp = depth.load;
    d.storeOp = depth.store;
    d.clearValue.depthStencil = {depth.clear, 0};
    VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
    info.renderArea = {{0, 0}, extent};
    info.layerCount = 1;
    info.colorAttachmentCount = 1;
    info.pColorAttachments = &c;
    info.pDepthAttachment = depth.view ? &d : nullptr;
    vkCmdBeginRendering(cmd, &info);
    const VkViewport viewport{0.0f, 0.0f, float(extent.width), float(extent.height), 0.0f, 1.0f};
    const VkRect2D scissor{{0, 0}, extent};
    vkCmdSetViewport(cmd, 0, 1, &viewport);
    vkCmdSetScissor(cmd, 0, 1, &scissor);
}

} // namespace pbdsplat::gpu
