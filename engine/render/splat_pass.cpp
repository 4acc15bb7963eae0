#include "render/splat_pass.h"

#include "gpu/uniform_sets.h"
#include "splat/gaussian_record.h"

namespace pbdsplat::render {

core::Result<SplatPass> SplatPass::create(const gpu::Context& ctx, VkFormat color, VkFormat depth) {
    if (!ctx.caps().geometry_shader)
        return core::make_error("device '" + ctx.caps().name +
                                "' has no geometry shaders, which the splat pass needs (try another device with "
                                "PBDSPLAT_DEVICE)");
    SplatPass p;
    auto set_layout = gpu::create_uniform_layout(ctx, VK_SHADER_STAGE_GEOMETRY_BIT | VK_SHADER_STAGE_FRAGMENT_BIT);
    if (!set_layout.ok()) return set_layout.error();
    p.set_layout_ = std::move(set_layout).value();
    const VkDescriptorSetLayout layout_handle = p.set_layout_.get();

    VkPipelineLayoutCreateInfo layout_info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    layout_info.setLayoutCount = 1;
    layout_info.pSetLayouts = &layout_handle;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    PBDSPLAT_VK_TRY(vkCreatePipelineLayout(ctx.vk(), &layout_info, nullptr, &layout));
    p.layout_ = gpu::PipelineLayout(ctx.vk(), layout);

    gpu::GraphicsPipelineDesc desc;
    desc.stages = {{VK_SHADER_STAGE_VERTEX_BIT, "splat.vert"},
                   {VK_SHADER_STAGE_GEOMETRY_BIT, "splat.geom"},
                   {VK_SHADER_STAGE_FRAGMENT_BIT, "splat.frag"}};
    desc.bindings = {{0, sizeof(splat::GaussianRecord), VK_VERTEX_INPUT_RATE_VERTEX}};
    desc.attributes = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, SPLAT_OFFSET_POSITION},
                       {1, 0, VK_FORMAT_R16G16_SNORM, SPLAT_OFFSET_NORMAL},
                       {2, 0, VK_FORMAT_R8G8B8A8_UNORM, SPLAT_OFFSET_COLOR},
                       {3, 0, VK_FORMAT_R16G16_SFLOAT, SPLAT_OFFSET_SCALE_OPACITY}};
    desc.topology = VK_PRIMITIVE_TOPOLOGY_POINT_LIST;
    desc.color_format = color;
    desc.depth_format = depth;
    desc.layout = layout;
    desc.stages[2].second = "splat_visibility.frag";
    desc.color_write = false;
    desc.specialization = 1u;  // k_visibility_pass
    auto visibility = gpu::create_graphics_pipeline(ctx, desc);
    if (!visibility.ok()) return visibility.error();
    p.visibility_ = std::move(visibility).value();

    desc.stages[2].second = "splat.frag";
    desc.color_write = true;
    desc.specialization.reset();
    desc.depth_write = false;
    desc.blend = gpu::BlendMode::over_premultiplied;
    auto over = gpu::create_graphics_pipeline(ctx, desc);
    if (!over.ok()) return over.error();
    p.over_ = std::move(over).value();
    // Additive splats do not occlude one another: order does not matter, no visibility pass.
    desc.blend = gpu::BlendMode::additive;
    auto additive = gpu::create_graphics_pipeline(ctx, desc);
    if (!additive.ok()) return additive.error();
    p.additive_ = std::move(additive).value();
    return p;
}

void SplatPass::record(VkCommandBuffer cmd, Blend blend, VkDescriptorSet frame_set, VkBuffer records,
                       uint32_t count) const {
    if (count == 0) return;
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_.get(), 0, 1, &frame_set, 0, nullptr);
    const VkDeviceSize offset = 0;
    vkCmdBindVertexBuffers(cmd, 0, 1, &records, &offset);
    if (blend == Blend::over) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, visibility_.get());
        vkCmdDraw(cmd, count, 1, 0, 0);
    }
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, blend == Blend::additive ? additive_.get() : over_.get());
    vkCmdDraw(cmd, count, 1, 0, 0);
}

} // namespace pbdsplat::render
