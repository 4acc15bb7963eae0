#include "render/occluder_pass.h"

#include <algorithm>
#include <cstring>

#include "core/assert.h"
#include "gpu/rendering.h"
#include "gpu/vk.h"

namespace pbdsplat::render {

namespace {

struct OccluderPush {
    float view_proj[16];
    float view_z[4];
    float eye_push[4];
};
static_assert(sizeof(OccluderPush) == 96, "occluder.vert's push block");

// Grows `buffer` to hold `bytes` (with room to spare, so a run of cuts does not reallocate
// every frame); its slot's previous frame has retired, so the old one may go.
core::Status fit(gpu::Context& ctx, gpu::Buffer& buffer, VkDeviceSize bytes, VkBufferUsageFlags usage) {
    if (buffer && buffer.size() >= bytes) return core::Status::success();
    auto b = gpu::Buffer::create(ctx, std::max<VkDeviceSize>(bytes + bytes / 4, 256), usage, gpu::MemoryUsage::upload);
    if (!b.ok()) return b.error();
    buffer = std::move(b).value();
    return core::Status::success();
}

} // namespace

float occluder_simplify_share(const gpu::DeviceCaps& caps) { return caps.type == "cpu" ? 0.1f : 0.0f; }

core::Result<OccluderPass> OccluderPass::create(gpu::Context& ctx, uint32_t width, uint32_t height, uint32_t slots, VkFormat depth_format) {
    OccluderPass o;
    o.ctx_ = &ctx;
    o.extent_ = {width, height};
    o.slots_.resize(std::max(1u, slots));
    auto image = gpu::Image::create_2d(ctx, width, height, k_occluder_format,
                                       VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT, VK_IMAGE_ASPECT_COLOR_BIT);
    if (!image.ok()) return image.error();
    o.image_ = std::move(image).value();
    // The geometry and mesh paths' front stages read it too, to drop the splats it hides whole
    // (SplatPass::cull_occluded).
    const VkImageView view = o.image_.view();
    const gpu::DeviceCaps& caps = ctx.caps();
    VkShaderStageFlags readers = VK_SHADER_STAGE_FRAGMENT_BIT;
    VkPipelineStageFlags2 reading = VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT;
    if (caps.geometry_shader) {
        readers |= VK_SHADER_STAGE_GEOMETRY_BIT;
        reading |= VK_PIPELINE_STAGE_2_GEOMETRY_SHADER_BIT;
    }
    if (caps.mesh_shader) {
        readers |= VK_SHADER_STAGE_MESH_BIT_EXT;
        reading |= VK_PIPELINE_STAGE_2_MESH_SHADER_BIT_EXT;
    }
    o.sampled_use_ = {{reading, VK_ACCESS_2_SHADER_READ_BIT}, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
    auto sampled = gpu::SampledImageSet::create(ctx, std::span<const VkImageView>(&view, 1), readers);
    if (!sampled.ok()) return sampled.error();
    o.sampled_ = std::move(sampled).value();

    auto layout = gpu::create_pipeline_layout(ctx, std::span<const VkDescriptorSetLayout>{}, {VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(OccluderPush)});
    if (!layout.ok()) return layout.error();
    o.layout_ = std::move(layout).value();
    gpu::GraphicsPipelineDesc desc;
    desc.stages = {{VK_SHADER_STAGE_VERTEX_BIT, "occluder.vert"}, {VK_SHADER_STAGE_FRAGMENT_BIT, "occluder.frag"}};
    desc.bindings = {{0, sizeof(Vec4f), VK_VERTEX_INPUT_RATE_VERTEX}};
    desc.attributes = {{0, 0, VK_FORMAT_R32G32B32A32_SFLOAT, 0}};
    desc.color_format = k_occluder_format;
    desc.depth_format = depth_format;
    desc.cull = VK_CULL_MODE_NONE;  // an open body's inside occludes as well as its outside
    desc.layout = o.layout_.get();
    auto pipeline = gpu::create_graphics_pipeline(ctx, desc);
    if (!pipeline.ok()) return pipeline.error();
    o.pipeline_ = std::move(pipeline).value();
    desc.cull = VK_CULL_MODE_BACK_BIT;
    auto one_sided = gpu::create_graphics_pipeline(ctx, desc);
    if (!one_sided.ok()) return one_sided.error();
    o.one_sided_ = std::move(one_sided).value();
    return o;
}

core::Status OccluderPass::set_mesh(std::span<const Vec4f> positions, std::span<const std::array<uint32_t, 3>> triangles, uint32_t slot_index,
                                    size_t one_sided) {
    PBDSPLAT_ASSERT(slot_index < slots_.size(), "OccluderPass: slot out of range; create it with one slot per frame in flight");
    Slot& slot = slots_[slot_index];
    PBDSPLAT_TRY(fit(*ctx_, slot.vertices, positions.size_bytes(), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT));
    PBDSPLAT_TRY(fit(*ctx_, slot.indices, triangles.size_bytes(), VK_BUFFER_USAGE_INDEX_BUFFER_BIT));
    if (!positions.empty()) std::memcpy(slot.vertices.mapped(), positions.data(), positions.size_bytes());
    if (!triangles.empty()) std::memcpy(slot.indices.mapped(), triangles.data(), triangles.size_bytes());
    slot.index_count = uint32_t(triangles.size() * 3);
    slot.one_sided_indices = uint32_t(std::min(one_sided, triangles.size()) * 3);
    return core::Status::success();
}

void OccluderPass::record(VkCommandBuffer cmd, const Camera& c, float push_back, VkImageView depth, uint32_t slot_index) const {
    PBDSPLAT_ASSERT(slot_index < slots_.size(), "OccluderPass: slot out of range; create it with one slot per frame in flight");
    const Slot& slot = slots_[slot_index];
    const Mat4f view = math::look_at(c.eye, c.target, c.up);
    const Mat4f proj = math::perspective(math::radians(c.fov_y_degrees), float(extent_.width) / float(extent_.height), c.z_near, c.z_far);
    OccluderPush push{};
    const Mat4f view_proj = proj * view;
    std::memcpy(push.view_proj, view_proj.data(), sizeof(push.view_proj));  // column-major, as GLSL reads it
    for (int k = 0; k < 4; ++k) push.view_z[k] = view(2, k);
    push.eye_push[0] = c.eye.x(), push.eye_push[1] = c.eye.y(), push.eye_push[2] = c.eye.z(), push.eye_push[3] = push_back;
    const gpu::ColorTarget target{image_.view(), VK_ATTACHMENT_LOAD_OP_CLEAR, {}};
    gpu::begin_rendering(cmd, extent_, target, {depth, VK_ATTACHMENT_LOAD_OP_LOAD, VK_ATTACHMENT_STORE_OP_STORE});
    if (slot.index_count > 0) {
        const VkDeviceSize offset = 0;
        const VkBuffer vb = slot.vertices.handle();
        vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &offset);
        vkCmdBindIndexBuffer(cmd, slot.indices.handle(), 0, VK_INDEX_TYPE_UINT32);
        // Both pipelines share the layout, so the push constants bound once hold for both.
        vkCmdPushConstants(cmd, layout_.get(), VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(push), &push);
        if (slot.one_sided_indices > 0) {
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, one_sided_.get());
            vkCmdDrawIndexed(cmd, slot.one_sided_indices, 1, 0, 0, 0);
        }
        if (slot.index_count > slot.one_sided_indices) {
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.get());
            vkCmdDrawIndexed(cmd, slot.index_count - slot.one_sided_indices, 1, slot.one_sided_indices, 0, 0);
        }
    }
    vkCmdEndRendering(cmd);
}

} // namespace pbdsplat::render
