#include "render/ground.h"

namespace pbdsplat::render {

core::Result<GroundPass> GroundPass::create(const gpu::Context& ctx, VkFormat color, VkFormat depth, VkDescriptorSetLayout frame_layout) {
    GroundPass g;
    const VkPushConstantRange push{VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(gpu_types::GroundPush)};
    auto layout = gpu::create_pipeline_layout(ctx, frame_layout, push);
    if (!layout.ok()) return layout.error();
    g.layout_ = std::move(layout).value();
    gpu::GraphicsPipelineDesc desc;
    desc.stages = {{VK_SHADER_STAGE_VERTEX_BIT, "ground.vert"}, {VK_SHADER_STAGE_FRAGMENT_BIT, "ground.frag"}};
    desc.color_format = color;
    desc.depth_format = depth;
    desc.layout = g.layout_.get();
    desc.blend = gpu::BlendMode::over_premultiplied;  // the rim fades into the background
    auto pipeline = gpu::create_graphics_pipeline(ctx, desc);
    if (!pipeline.ok()) return pipeline.error();
    g.pipeline_ = std::move(pipeline).value();
    return g;
}

void GroundPass::record(VkCommandBuffer cmd, VkDescriptorSet frame_set, const Ground& ground) const {
    gpu_types::GroundPush p{};
    const Vec3f n = ground.normal.normalized();
    p.plane = {n.x(), n.y(), n.z(), ground.offset};
    p.disc = {ground.centre.x(), ground.centre.y(), ground.centre.z(), ground.radius};
    p.albedo = {ground.albedo.x(), ground.albedo.y(), ground.albedo.z(), 0.0f};
    static_assert(GROUND_SHADOWS == 4, "the strengths below fill one vec4");
    for (size_t k = 0; k < ground.shadows.size(); ++k) {
        const Ground::Shadow& s = ground.shadows[k];
        p.shadow[k] = {s.centre.x(), s.centre.y(), s.centre.z(), s.radius};
    }
    const auto& s = ground.shadows;
    p.strength = {s[0].strength, s[1].strength, s[2].strength, s[3].strength};
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.get());
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_.get(), 0, 1, &frame_set, 0, nullptr);
    vkCmdPushConstants(cmd, layout_.get(), VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(p), &p);
    vkCmdDraw(cmd, 6, 1, 0, 0);
}

} // namespace pbdsplat::render
