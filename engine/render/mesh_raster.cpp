#include "render/mesh_raster.h"

#include <algorithm>
#include <cstring>

#include "core/assert.h"
#include "render/frame_uniforms.h"

namespace pbdsplat::render {

core::Result<std::unique_ptr<MeshRaster>> MeshRaster::create(gpu::Context& ctx, const MeshRasterOptions& options) {
    auto m = std::unique_ptr<MeshRaster>(new MeshRaster());
    m->ctx_ = &ctx;
    auto target = OffscreenTarget::create(ctx, options.width, options.height, 1);
    if (!target.ok()) return target.error();
    m->target_ = std::move(target).value();
    PBDSPLAT_TRY(m->create_slots(ctx, options));
    auto environment = make_environment_texture(ctx, options.environment_map, options.sky_sun);
    if (!environment.ok()) return environment.error();
    m->environment_ = std::move(environment).value();
    auto textures = MeshTextureSets::create(ctx);
    if (!textures.ok()) return textures.error();
    m->textures_ = std::move(textures).value();
    PBDSPLAT_TRY(m->create_frame_set(ctx));
    PBDSPLAT_TRY(m->create_pipelines(ctx));
    return m;
}

core::Status MeshRaster::create_slots(gpu::Context& ctx, const MeshRasterOptions& options) {
    const size_t nv = std::max<size_t>(1, options.max_vertices), nt = std::max<size_t>(1, options.max_triangles);
    struct Want { gpu::Buffer* buffer; VkDeviceSize bytes; VkBufferUsageFlags usage; };
    slots_.resize(std::max(1u, options.slots));
    for (Slot& slot : slots_) {
        // The positions double as the frame set's storage binding, which no mesh shader reads.
        for (const Want& w : {Want{&slot.vertices, nv * sizeof(Vec4f), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT},
                              Want{&slot.normals, nv * sizeof(Vec3f), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT},
                              Want{&slot.colors, nv * sizeof(Vec3f), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT},
                              Want{&slot.uvs, nv * sizeof(Vec2f), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT},
                              Want{&slot.indices, nt * 3 * sizeof(uint32_t), VK_BUFFER_USAGE_INDEX_BUFFER_BIT}}) {
            auto b = gpu::Buffer::create(ctx, w.bytes, w.usage, gpu::MemoryUsage::upload);
            if (!b.ok()) return b.error();
            *w.buffer = std::move(b).value();
        }
        std::memset(slot.normals.mapped(), 0, slot.normals.size());
        std::memset(slot.uvs.mapped(), 0, slot.uvs.size());
        std::fill_n(static_cast<float*>(slot.colors.mapped()), slot.colors.size() / sizeof(float), 1.0f);
    }
    return core::Status::success();
}

core::Status MeshRaster::create_frame_set(gpu::Context& ctx) {
    gpu::FrameSetStages stages;
    stages.uniforms = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
    stages.texture = VK_SHADER_STAGE_FRAGMENT_BIT;
    stages.storage = VK_SHADER_STAGE_VERTEX_BIT;
    auto set_layout = gpu::create_frame_layout(ctx, stages);
    if (!set_layout.ok()) return set_layout.error();
    set_layout_ = std::move(set_layout).value();
    gpu::FrameSetResources extra;
    extra.texture_view = environment_.texture.view();
    extra.texture_sampler = environment_.texture.sampler();
    for (const Slot& slot : slots_) extra.storage.push_back(slot.vertices.handle());
    auto uniforms = gpu::UniformSets::create(ctx, set_layout_.get(), uint32_t(slots_.size()), sizeof(gpu_types::FrameUniforms), &extra);
    if (!uniforms.ok()) return uniforms.error();
    uniforms_ = std::move(uniforms).value();
    return core::Status::success();
}

core::Status MeshRaster::create_pipelines(gpu::Context& ctx) {
    const VkDescriptorSetLayout sets[2] = {set_layout_.get(), textures_.layout()};
    auto pipeline_layout = gpu::create_pipeline_layout(ctx, sets, {VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(float) * 4});
    if (!pipeline_layout.ok()) return pipeline_layout.error();
    layout_ = std::move(pipeline_layout).value();
    gpu::GraphicsPipelineDesc desc;
    desc.stages = {{VK_SHADER_STAGE_VERTEX_BIT, "mesh.vert"}, {VK_SHADER_STAGE_FRAGMENT_BIT, "mesh.frag"}};
    desc.bindings = {{0, sizeof(Vec4f), VK_VERTEX_INPUT_RATE_VERTEX},
                     {1, sizeof(Vec3f), VK_VERTEX_INPUT_RATE_VERTEX},
                     {2, sizeof(Vec3f), VK_VERTEX_INPUT_RATE_VERTEX},
                     {3, sizeof(Vec2f), VK_VERTEX_INPUT_RATE_VERTEX}};
    desc.attributes = {{0, 0, VK_FORMAT_R32G32B32A32_SFLOAT, 0},
                       {1, 1, VK_FORMAT_R32G32B32_SFLOAT, 0},
                       {2, 2, VK_FORMAT_R32G32B32_SFLOAT, 0},
                       {3, 3, VK_FORMAT_R32G32_SFLOAT, 0}};
    desc.color_format = k_color_format;
    desc.depth_format = k_depth_format;
    desc.layout = layout_.get();
    desc.specialization = {1u};  // k_mask
    auto mask = gpu::create_graphics_pipeline(ctx, desc);
    if (!mask.ok()) return mask.error();
    mask_ = std::move(mask).value();
    desc.specialization = {0u};
    auto shaded = gpu::create_graphics_pipeline(ctx, desc);
    if (!shaded.ok()) return shaded.error();
    shaded_ = std::move(shaded).value();
    return core::Status::success();
}

core::Status MeshRaster::set_mesh(std::span<const Vec4f> positions, std::span<const std::array<uint32_t, 3>> triangles,
                                  std::span<const Vec3f> normals, uint32_t slot_index, std::span<const Vec3f> colors,
                                  const MeshTexturing* texturing) {
    PBDSPLAT_ASSERT(slot_index < slots_.size(), "MeshRaster: slot out of range; create it with options.slots");
    Slot& slot = slots_[slot_index];
    if (positions.size_bytes() > slot.vertices.size() || triangles.size() * 3 * sizeof(uint32_t) > slot.indices.size())
        return core::make_error("the mesh is larger than this MeshRaster was created for");
    if (!normals.empty() && normals.size() != positions.size())
        return core::make_error("MeshRaster::set_mesh: " + std::to_string(normals.size()) + " normals for " +
                                std::to_string(positions.size()) + " positions");
    if (!colors.empty() && colors.size() != positions.size())
        return core::make_error("MeshRaster::set_mesh: " + std::to_string(colors.size()) + " colours for " +
                                std::to_string(positions.size()) + " positions");
    if (!colors.empty()) {
        std::memcpy(slot.colors.mapped(), colors.data(), colors.size_bytes());
        slot.colored = true;
    } else if (slot.colored) {
        std::fill_n(static_cast<float*>(slot.colors.mapped()), slot.colors.size() / sizeof(float), 1.0f);
        slot.colored = false;
    }
    std::memcpy(slot.vertices.mapped(), positions.data(), positions.size_bytes());
    if (!normals.empty()) std::memcpy(slot.normals.mapped(), normals.data(), normals.size_bytes());
    if (texturing) {
        if (texturing->uv.size() != positions.size() || texturing->triangle_texture.size() != triangles.size())
            return core::make_error("MeshRaster::set_mesh: texturing needs a texture coordinate per position and a texture per triangle");
        return set_texturing(slot_index, triangles, *texturing);
    }
    std::memcpy(slot.indices.mapped(), triangles.data(), triangles.size() * 3 * sizeof(uint32_t));
    slot.runs.assign(1, Run{0, uint32_t(triangles.size() * 3), -1});
    return core::Status::success();
}

core::Status MeshRaster::set_texturing(uint32_t slot_index, std::span<const std::array<uint32_t, 3>> triangles,
                                       const MeshTexturing& texturing) {
    Slot& slot = slots_[slot_index];
    std::memcpy(slot.uvs.mapped(), texturing.uv.data(), texturing.uv.size_bytes());
    // One run per texture: a draw binds one texture, so the triangles go in the index buffer
    // grouped by theirs (in their order within a group).
    std::vector<uint32_t> order(triangles.size());
    for (uint32_t t = 0; t < order.size(); ++t) order[t] = t;
    std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
        return texturing.triangle_texture[a] < texturing.triangle_texture[b];
    });
    auto* indices = static_cast<std::array<uint32_t, 3>*>(slot.indices.mapped());
    slot.runs.clear();
    for (uint32_t k = 0; k < order.size(); ++k) {
        indices[k] = triangles[order[k]];
        int32_t texture = texturing.triangle_texture[order[k]];
        if (texture >= int32_t(textures_.size())) texture = -1;
        if (slot.runs.empty() || slot.runs.back().texture != texture) slot.runs.push_back(Run{k * 3, 0, texture});
        slot.runs.back().index_count += 3;
    }
    return core::Status::success();
}

void MeshRaster::draw(VkCommandBuffer cmd, const FrameInputs& inputs, MeshView view, const Vec3f& albedo, uint32_t slot_index) {
    PBDSPLAT_ASSERT(slot_index < slots_.size(), "MeshRaster: slot out of range; create it with options.slots");
    const Slot& slot = slots_[slot_index];
    const auto u = make_frame_uniforms(inputs, target_.width(), target_.height(), &environment_.sh);
    std::memcpy(uniforms_.mapped(slot_index), &u, sizeof(u));
    const float clear_mask[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    target_.begin(cmd, view == MeshView::mask ? clear_mask : inputs.background.data());
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, view == MeshView::mask ? mask_.get() : shaded_.get());
    const VkDescriptorSet set = uniforms_.set(slot_index);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_.get(), 0, 1, &set, 0, nullptr);
    const VkDeviceSize offsets[4] = {0, 0, 0, 0};
    const VkBuffer vbs[4] = {slot.vertices.handle(), slot.normals.handle(), slot.colors.handle(), slot.uvs.handle()};
    vkCmdBindVertexBuffers(cmd, 0, 4, vbs, offsets);
    vkCmdBindIndexBuffer(cmd, slot.indices.handle(), 0, VK_INDEX_TYPE_UINT32);
    for (const Run& run : slot.runs) {
        // The albedo's w says whether the run samples its texture (the white texel's set is
        // bound where it has none, since the pipeline reads set 1 either way).
        const float push[4] = {albedo.x(), albedo.y(), albedo.z(), run.texture >= 0 ? 1.0f : 0.0f};
        vkCmdPushConstants(cmd, layout_.get(), VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(push), push);
        const VkDescriptorSet texture = textures_.set_of(run.texture);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_.get(), 1, 1, &texture, 0, nullptr);
        vkCmdDrawIndexed(cmd, run.index_count, 1, run.first_index, 0, 0);
    }
    target_.end(cmd);
}

} // namespace pbdsplat::render
