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
    auto u = gpu::Buffer::create(ctx, sizeof(gpu_types::FrameUniforms), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, gpu::MemoryUsage::upload);
    if (!u.ok()) return u.error();
    m->uniforms_ = std::move(u).value();

    VkDescriptorSetLayoutBinding ubo{0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, VK_SHADER_STAGE_VERTEX_BIT, nullptr};
    VkDescriptorSetLayoutCreateInfo set_info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    set_info.bindingCount = 1;
    set_info.pBindings = &ubo;
    VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
    PBDSPLAT_VK_TRY(vkCreateDescriptorSetLayout(ctx.vk(), &set_info, nullptr, &set_layout));
    m->set_layout_ = gpu::DescriptorSetLayout(ctx.vk(), set_layout);
    VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1};
    VkDescriptorPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    pool_info.maxSets = 1;
    pool_info.poolSizeCount = 1;
    pool_info.pPoolSizes = &size;
    VkDescriptorPool pool = VK_NULL_HANDLE;
    PBDSPLAT_VK_TRY(vkCreateDescriptorPool(ctx.vk(), &pool_info, nullptr, &pool));
    m->pool_ = gpu::DescriptorPool(ctx.vk(), pool);
    VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    alloc.descriptorPool = pool;
    alloc.descriptorSetCount = 1;
    alloc.pSetLayouts = &set_layout;
    PBDSPLAT_VK_TRY(vkAllocateDescriptorSets(ctx.vk(), &alloc, &m->set_));
    VkDescriptorBufferInfo buffer_info{m->uniforms_.handle(), 0, sizeof(gpu_types::FrameUniforms)};
    VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    write.dstSet = m->set_;
    write.descriptorCount = 1;
    write.descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    write.pBufferInfo = &buffer_info;
    vkUpdateDescriptorSets(ctx.vk(), 1, &write, 0, nullptr);

    VkPipelineLayoutCreateInfo layout_info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    layout_info.setLayoutCount = 1;
    layout_info.pSetLayouts = &set_layout;
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
    std::memcpy(uniforms_.mapped(), &u, sizeof(u));
    const float clear[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    target_.begin(cmd, clear);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.get());
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_.get(), 0, 1, &set_, 0, nullptr);
    const VkDeviceSize offset = 0;
    const VkBuffer vb = vertices_.handle();
    vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &offset);
    vkCmdBindIndexBuffer(cmd, indices_.handle(), 0, VK_INDEX_TYPE_UINT32);
    vkCmdDrawIndexed(cmd, index_count_, 1, 0, 0, 0);
    target_.end(cmd);
}

} // namespace pbdsplat::render
