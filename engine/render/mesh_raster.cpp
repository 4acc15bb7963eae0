#include "render/mesh_raster.h"

#include <cstring>

#include "render/frame_uniforms.h"

namespace pbdsplat::render {

core::Result<std::unique_ptr<MeshRaster>> MeshRaster::create(gpu::Context& ctx, uint32_t width, uint32_t height,
                                                             size_t max_vertices, size_t max_triangles) {
    auto m = std::unique_ptr<MeshRaster>(new MeshRaster());
    m->ctx_ = &ctx;
    auto target = OffscreenTarget::create(ctx, width, height, 1);
    if (!target.ok()) return target.error();
    m->target_ = std::move(target).value();
    auto v = gpu::Buffer::create(ctx, std::max<size_t>(1, max_vertices) * sizeof(Vec4f), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT,
                                 gpu::MemoryUsage::upload);
    if (!v.ok()) return v.error();
    m->vertices_ = std::move(v).value();
    auto i = gpu::Buffer::create(ctx, std::max<size_t>(1, max_triangles) * 3 * sizeof(uint32_t), VK_BUFFER_USAGE_INDEX_BUFFER_BIT,
                                 gpu::MemoryUsage::upload);
    if (!i.ok()) return i.error();
    m->indices_ = std::move(i).value();
    auto set_layout = gpu::create_uniform_layout(ctx, VK_SHADER_STAGE_VERTEX_BIT);
    if (!set_layout.ok()) return set_layout.error();
    m->set_layout_ = std::move(set_layout).value();
    const VkDescriptorSetLayout set_layout_handle = m->set_layout_.get();
    auto uniforms = gpu::UniformSets::create(ctx, set_layout_handle, 1, sizeof(gpu_types::FrameUniforms));
    if (!uniforms.ok()) return uniforms.error();
    m->uniforms_ = std::move(uniforms).value();

    VkPipelineLayoutCreateInfo layout_info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    layout_info.setLayoutCount = 1;
    layout_info.pSetLayouts = &set_layout_handle;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    PBDSPLAT_VK_TRY(vkCreatePipelineLayout(ctx.vk(), &layout_info, nullptr, &layout));
    m->layout_ = gpu::PipelineLayout(ctx.vk(), layout);
    gpu::GraphicsPipelineDesc desc;
    desc.stages = {{VK_SHADER_STAGE_VERTEX_BIT, "mesh.vert"}, {VK_SHADER_STAGE_FRAGMENT_BIT, "mesh.frag"}};
    desc.bindings = {{0, sizeof(Vec4f), VK_VERTEX_INPUT_RATE_VERTEX}};
    desc.attributes = {{0, 0, VK_FORMAT_R32G32B32A32_SFLOAT, 0}};
    desc.color_format = k_color_format;
    desc.depth_format = k_depth_format;
    desc.layout = layout;
    auto pipeline = gpu::create_graphics_pipeline(ctx, desc);
    if (!pipeline.ok()) return pipeline.error();
    m->pipeline_ = std::move(pipeline).value();
    return m;
}

core::Status MeshRaster::set_mesh(std::span<const Vec4f> positions, std::span<const std::array<uint32_t, 3>> triangles) {
    if (positions.size_bytes() > vertices_.size() || triangles.size() * 3 * sizeof(uint32_t) > indices_.size())
        return core::make_error("the mesh is larger than this MeshRaster was created for");
    std::memcpy(vertices_.mapped(), positions.data(), positions.size_bytes());
    std::memcpy(indices_.mapped(), triangles.data(), triangles.size() * 3 * sizeof(uint32_t));
    index_count_ = uint32_t(triangles.size() * 3);
    return core::Status::success();
}

void MeshRaster::draw(VkCommandBuffer cmd, const FrameInputs& inputs) {
    const auto u = make_frame_uniforms(inputs, target_.width(), target_.height());
    std::memcpy(uniforms_.mapped(0), &u, sizeof(u));
    const float clear[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    target_.begin(cmd, clear);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.get());
    const VkDescriptorSet set = uniforms_.set(0);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_.get(), 0, 1, &set, 0, nullptr);
    const VkDeviceSize offset = 0;
    const VkBuffer vb = vertices_.handle();
    vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &offset);
    vkCmdBindIndexBuffer(cmd, indices_.handle(), 0, VK_INDEX_TYPE_UINT32);
    vkCmdDrawIndexed(cmd, index_count_, 1, 0, 0, 0);
    target_.end(cmd);
}

} // namespace pbdsplat::render
