#include "render/overlay.h"

#include <cstring>

#include "gpu/pipeline.h"
#include "gpu/rendering.h"

namespace pbdsplat::render {

core::Result<std::unique_ptr<OverlayPass>> OverlayPass::create(gpu::Context& ctx, uint32_t width, uint32_t height,
                                                               VkFormat target_format, uint32_t slots) {
    auto o = std::unique_ptr<OverlayPass>(new OverlayPass());
    auto image = gpu::Image::create_2d(ctx, width, height, VK_FORMAT_R8G8B8A8_UNORM,
                                       VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT, VK_IMAGE_ASPECT_COLOR_BIT);
    if (!image.ok()) return image.error();
    o->image_ = std::move(image).value();
    for (uint32_t i = 0; i < std::max(1u, slots); ++i) {
        auto b = gpu::Buffer::create(ctx, VkDeviceSize(width) * height * 4, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, gpu::MemoryUsage::upload);
        if (!b.ok()) return b.error();
        std::memset(b->mapped(), 0, b->size());
        o->staging_.push_back(std::move(b).value());
        o->staged_version_.push_back(0);
    }
    o->latest_ = core::ImageRgba8(width, height);

    // One texel per pixel: text stays crisp.
    auto set = gpu::SampledImageSet::create(ctx, o->image_.view());
    if (!set.ok()) return set.error();
    o->set_ = std::move(set).value();

    auto layout = gpu::create_pipeline_layout(ctx, o->set_.layout(), {VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(float) * 2});
    if (!layout.ok()) return layout.error();
    o->layout_ = std::move(layout).value();
    gpu::GraphicsPipelineDesc desc;
    desc.stages = {{VK_SHADER_STAGE_VERTEX_BIT, "overlay.vert"}, {VK_SHADER_STAGE_FRAGMENT_BIT, "overlay.frag"}};
    desc.color_format = target_format;
    desc.depth_format = VK_FORMAT_UNDEFINED;
    desc.depth_test = false;
    desc.depth_write = false;
    desc.blend = gpu::BlendMode::over_premultiplied;
    desc.layout = o->layout_.get();
    auto pipeline = gpu::create_graphics_pipeline(ctx, desc);
    if (!pipeline.ok()) return pipeline.error();
    o->pipeline_ = std::move(pipeline).value();
    return o;
}

void OverlayPass::set(const core::ImageRgba8& image) {
    if (image.width != latest_.width || image.height != latest_.height) return;  // sized at creation
    if (image.pixels == latest_.pixels) return;
    latest_.pixels = image.pixels;
    ++version_;
}

void OverlayPass::record_upload(VkCommandBuffer cmd, uint32_t slot) {
    // The slot's staging buffer is free: its previous frame has finished.
    if (staged_version_[slot] != version_) {
        std::memcpy(staging_[slot].mapped(), latest_.pixels.data(), latest_.pixels.size());
        staged_version_[slot] = version_;
    }
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {image_.width(), image_.height(), 1};
    vkCmdCopyBufferToImage(cmd, staging_[slot].handle(), image_.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
}

void OverlayPass::record_draw(VkCommandBuffer cmd, VkImageView target, VkExtent2D extent) const {
    gpu::begin_rendering(cmd, extent, {target});
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.get());
    const VkDescriptorSet set = set_.set();
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_.get(), 0, 1, &set, 0, nullptr);
    const float scale[2] = {float(extent.width) / float(image_.width()), float(extent.height) / float(image_.height())};
    vkCmdPushConstants(cmd, layout_.get(), VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(scale), scale);
    vkCmdDraw(cmd, 3, 1, 0, 0);
    vkCmdEndRendering(cmd);
}

} // namespace pbdsplat::render
