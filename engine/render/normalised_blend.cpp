#include "render/normalised_blend.h"

#include "gpu/pipeline.h"
#include "gpu/rendering.h"
#include "gpu/vk.h"

namespace pbdsplat::render {

core::Result<NormalisedBlend> NormalisedBlend::create(gpu::Context& ctx, uint32_t width, uint32_t height, VkFormat target_format) {
    NormalisedBlend n;
    n.extent_ = {width, height};
    VkImageView views[k_sum_layers];
    for (uint32_t i = 0; i < k_sum_layers; ++i) {
        auto image = gpu::Image::create_2d(ctx, width, height, k_accumulation_format,
                                           VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT, VK_IMAGE_ASPECT_COLOR_BIT);
        if (!image.ok()) return image.error();
        n.layers_[i] = std::move(image).value();
        views[i] = n.layers_[i].view();
    }

    // One set of images for every frame in flight, as the colour target: the graph's barriers
    // order the frames' uses of them.
    auto sums = gpu::SampledImageSet::create(ctx, views);
    if (!sums.ok()) return sums.error();
    n.sums_ = std::move(sums).value();

    auto layout = gpu::create_pipeline_layout(ctx, n.sums_.layout());
    if (!layout.ok()) return layout.error();
    n.layout_ = std::move(layout).value();
    gpu::GraphicsPipelineDesc desc;
    desc.stages = {{VK_SHADER_STAGE_VERTEX_BIT, "splat_resolve.vert"}, {VK_SHADER_STAGE_FRAGMENT_BIT, "splat_resolve.frag"}};
    desc.color_format = target_format;
    desc.depth_format = VK_FORMAT_UNDEFINED;
    desc.depth_test = false;
    desc.depth_write = false;
    desc.blend = gpu::BlendMode::over_premultiplied;
    desc.layout = n.layout_.get();
    auto pipeline = gpu::create_graphics_pipeline(ctx, desc);
    if (!pipeline.ok()) return pipeline.error();
    n.resolve_ = std::move(pipeline).value();
    return n;
}

void NormalisedBlend::begin_accumulation(VkCommandBuffer cmd, VkImageView depth, VkRect2D area) const {
    // Nothing reads the depth after the accumulation; its store still counts as a write.
    gpu::ColorTarget targets[k_sum_layers];
    for (uint32_t i = 0; i < k_sum_layers; ++i) targets[i] = {layers_[i].view(), VK_ATTACHMENT_LOAD_OP_CLEAR, {}};
    gpu::begin_rendering(cmd, extent_, targets, {depth, VK_ATTACHMENT_LOAD_OP_LOAD, VK_ATTACHMENT_STORE_OP_DONT_CARE}, area);
}

void NormalisedBlend::end_accumulation(VkCommandBuffer cmd) const { vkCmdEndRendering(cmd); }

void NormalisedBlend::record_resolve(VkCommandBuffer cmd, VkImageView target, VkRect2D area) const {
    gpu::begin_rendering(cmd, extent_, gpu::ColorTarget{target}, {}, area);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, resolve_.get());
    const VkDescriptorSet set = sums_.set();
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_.get(), 0, 1, &set, 0, nullptr);
    vkCmdDraw(cmd, 3, 1, 0, 0);
    vkCmdEndRendering(cmd);
}

} // namespace pbdsplat::render
