#include "render/overlay.h"

#include <cstring>

#include "gpu/pipeline.h"

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

    VkSamplerCreateInfo s{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    s.magFilter = s.minFilter = VK_FILTER_NEAREST;  // one texel per pixel: text stays crisp
    s.addressModeU = s.addressModeV = s.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    VkSampler sampler = VK_NULL_HANDLE;
    PBDSPLAT_VK_TRY(vkCreateSampler(ctx.vk(), &s, nullptr, &sampler));
    o->sampler_ = gpu::Sampler(ctx.vk(), sampler);

    const VkDescriptorSetLayoutBinding binding{0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr};
    VkDescriptorSetLayoutCreateInfo set_info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    set_info.bindingCount = 1;
    set_info.pBindings = &binding;
    VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
    PBDSPLAT_VK_TRY(vkCreateDescriptorSetLayout(ctx.vk(), &set_info, nullptr, &set_layout));
    o->set_layout_ = gpu::DescriptorSetLayout(ctx.vk(), set_layout);
    const VkDescriptorPoolSize pool_size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1};
    VkDescriptorPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    pool_info.maxSets = 1;
    pool_info.poolSizeCount = 1;
    pool_info.pPoolSizes = &pool_size;
    VkDescriptorPool pool = VK_NULL_HANDLE;
    PBDSPLAT_VK_TRY(vkCreateDescriptorPool(ctx.vk(), &pool_info, nullptr, &pool));
    o->pool_ = gpu::DescriptorPool(ctx.vk(), pool);
    VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    alloc.descriptorPool = pool;
    alloc.descriptorSetCount = 1;
    alloc.pSetLayouts = &set_layout;
    PBDSPLAT_VK_TRY(vkAllocateDescriptorSets(ctx.vk(), &alloc, &o->set_));
    const VkDescriptorImageInfo image_info{sampler, o->image_.view(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
    VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    write.dstSet = o->set_;
    write.descriptorCount = 1;
    write.descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    write.pImageInfo = &image_info;
    vkUpdateDescriptorSets(ctx.vk(), 1, &write, 0, nullptr);

    auto layout = gpu::create_pipeline_layout(ctx, set_layout, {VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(float) * 2});
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
    VkRenderingAttachmentInfo color{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    color.imageView = target;
    color.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    color.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
    color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
    info.renderArea = {{0, 0}, extent};
    info.layerCount = 1;
    info.colorAttachmentCount = 1;
    info.pColorAttachments = &color;
    vkCmdBeginRendering(cmd, &info);
    const VkViewport viewport{0.0f, 0.0f, float(extent.width), float(extent.height), 0.0f, 1.0f};
    const VkRect2D scissor{{0, 0}, extent};
    vkCmdSetViewport(cmd, 0, 1, &viewport);
    vkCmdSetScissor(cmd, 0, 1, &scissor);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.get());
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_.get(), 0, 1, &set_, 0, nullptr);
    const float scale[2] = {float(extent.width) / float(image_.width()), float(extent.height) / float(image_.height())};
    vkCmdPushConstants(cmd, layout_.get(), VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(scale), scale);
    vkCmdDraw(cmd, 3, 1, 0, 0);
    vkCmdEndRendering(cmd);
}

} // namespace pbdsplat::render
