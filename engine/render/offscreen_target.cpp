#include "render/offscreen_target.h"

#include <cstring>

#include "gpu/barriers.h"
#include "gpu/rendering.h"

namespace pbdsplat::render {

core::Result<OffscreenTarget> OffscreenTarget::create(gpu::Context& ctx, uint32_t width, uint32_t height,
                                                      uint32_t frames_in_flight) {
    OffscreenTarget t;
    auto color = gpu::Image::create_2d(ctx, width, height, k_color_format,
                                       VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                                       VK_IMAGE_ASPECT_COLOR_BIT);
    if (!color.ok()) return color.error();
    t.color_ = std::move(color).value();
    auto depth = gpu::Image::create_2d(ctx, width, height, k_depth_format, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
                                       VK_IMAGE_ASPECT_DEPTH_BIT);
    if (!depth.ok()) return depth.error();
    t.depth_ = std::move(depth).value();
    for (uint32_t i = 0; i < frames_in_flight; ++i) {
        auto b = gpu::Buffer::create(ctx, VkDeviceSize(width) * height * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                     gpu::MemoryUsage::readback);
        if (!b.ok()) return b.error();
        t.readback_.push_back(std::move(b).value());
    }
    return t;
}

void OffscreenTarget::begin(VkCommandBuffer cmd, const float clear_rgba[4], bool keep_depth) {
    gpu::ColorTarget color{color_.view(), VK_ATTACHMENT_LOAD_OP_CLEAR, {}};
    std::memcpy(color.clear.float32, clear_rgba, sizeof(float) * 4);
    gpu::begin_rendering(cmd, {width(), height()}, color,
                         {depth_.view(), VK_ATTACHMENT_LOAD_OP_CLEAR,
                          keep_depth ? VK_ATTACHMENT_STORE_OP_STORE : VK_ATTACHMENT_STORE_OP_DONT_CARE, 1.0f});
}

void OffscreenTarget::resume(VkCommandBuffer cmd) {
    gpu::begin_rendering(cmd, {width(), height()}, gpu::ColorTarget{color_.view(), VK_ATTACHMENT_LOAD_OP_LOAD, {}},
                         {depth_.view(), VK_ATTACHMENT_LOAD_OP_LOAD, VK_ATTACHMENT_STORE_OP_STORE});
}

void OffscreenTarget::end(VkCommandBuffer cmd) { vkCmdEndRendering(cmd); }

void OffscreenTarget::record_readback(VkCommandBuffer cmd, uint32_t slot) {
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {width(), height(), 1};
    vkCmdCopyImageToBuffer(cmd, color_.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback_[slot].handle(), 1,
                           &region);
    // Make the copy visible to the host once the fence signals.
    gpu::buffer_barrier(cmd, readback_[slot].handle(), {VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT},
                        {VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT});
}

core::ImageRgba8 OffscreenTarget::read(uint32_t slot) const {
    core::ImageRgba8 img(width(), height());
    std::memcpy(img.pixels.data(), readback_[slot].mapped(), img.pixels.size());
    return img;
}

} // namespace pbdsplat::render
