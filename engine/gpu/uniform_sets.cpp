#include "gpu/uniform_sets.h"

namespace pbdsplat::gpu {

core::Result<DescriptorSetLayout> create_uniform_layout(const Context& ctx, VkShaderStageFlags stages) {
    VkDescriptorSetLayoutBinding ubo{0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, stages, nullptr};
    VkDescriptorSetLayoutCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    info.bindingCount = 1;
    info.pBindings = &ubo;
    VkDescriptorSetLayout layout = VK_NULL_HANDLE;
    PBDSPLAT_VK_TRY(vkCreateDescriptorSetLayout(ctx.vk(), &info, nullptr, &layout));
    return DescriptorSetLayout(ctx.vk(), layout);
}

core::Result<DescriptorSetLayout> create_frame_layout(const Context& ctx, const FrameSetStages& stages) {
    std::vector<VkDescriptorSetLayoutBinding> bindings = {
        {0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, stages.uniforms, nullptr},
        {1, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, stages.texture, nullptr},
        {2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, stages.storage, nullptr}};
    if (stages.shapes) bindings.push_back({3, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, stages.shapes, nullptr});
    if (stages.sh) bindings.push_back({4, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, stages.sh, nullptr});
    if (stages.order) bindings.push_back({5, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, stages.order, nullptr});
    if (stages.texcoords) bindings.push_back({6, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, stages.texcoords, nullptr});
    if (stages.textures && stages.texture_count)
        bindings.push_back({7, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, stages.texture_count, stages.textures, nullptr});
    VkDescriptorSetLayoutCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    info.bindingCount = uint32_t(bindings.size());
    info.pBindings = bindings.data();
    VkDescriptorSetLayout layout = VK_NULL_HANDLE;
    PBDSPLAT_VK_TRY(vkCreateDescriptorSetLayout(ctx.vk(), &info, nullptr, &layout));
    return DescriptorSetLayout(ctx.vk(), layout);
}

namespace {

// Set `set`'s bindings past its uniform buffer: 1, the texture, then 2-5 (records, shapes,
// view-dependent colour, their order) where the set has them; a list of one buffer serves every
// set, a longer one gives set `index` its own.
void write_extra(Context& ctx, VkDescriptorSet set, const FrameSetResources& extra, uint32_t index) {
    VkDescriptorImageInfo image{extra.texture_sampler, extra.texture_view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
    auto pick = [index](const std::vector<VkBuffer>& v) { return v.size() > 1 ? v[index] : v.front(); };
    std::vector<VkDescriptorBufferInfo> infos;
    infos.reserve(5);
    std::vector<VkWriteDescriptorSet> writes;
    VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    w.dstSet = set;
    w.descriptorCount = 1;
    w.dstBinding = 1;
    w.descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    w.pImageInfo = &image;
    writes.push_back(w);
    w.pImageInfo = nullptr;
    w.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    const std::pair<uint32_t, const std::vector<VkBuffer>*> buffers[5] = {
        {2, &extra.storage}, {3, &extra.shapes}, {4, &extra.sh}, {5, &extra.order}, {6, &extra.texcoords}};
    for (const auto& [binding, list] : buffers) {
        if (list->empty()) continue;
        infos.push_back({pick(*list), 0, VK_WHOLE_SIZE});
        w.dstBinding = binding;
        w.pBufferInfo = &infos.back();
        writes.push_back(w);
    }
    if (!extra.textures.empty()) {
        w.dstBinding = 7;
        w.descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
        w.descriptorCount = uint32_t(extra.textures.size());
        w.pBufferInfo = nullptr;
        w.pImageInfo = extra.textures.data();
        writes.push_back(w);
    }
    vkUpdateDescriptorSets(ctx.vk(), uint32_t(writes.size()), writes.data(), 0, nullptr);
}

} // namespace

core::Result<UniformSets> UniformSets::create(Context& ctx, VkDescriptorSetLayout layout, uint32_t count, VkDeviceSize bytes,
                                              const FrameSetResources* extra) {
    UniformSets u;
    const uint32_t images = 1 + (extra ? uint32_t(extra->textures.size()) : 0u);
    const VkDescriptorPoolSize sizes[3] = {{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, count},
                                           {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, images * count},
                                           {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 5 * count}};
    VkDescriptorPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    pool_info.maxSets = count;
    pool_info.poolSizeCount = extra ? 3 : 1;
    pool_info.pPoolSizes = sizes;
    VkDescriptorPool pool = VK_NULL_HANDLE;
    PBDSPLAT_VK_TRY(vkCreateDescriptorPool(ctx.vk(), &pool_info, nullptr, &pool));
    u.pool_ = DescriptorPool(ctx.vk(), pool);
    for (uint32_t i = 0; i < count; ++i) {
        auto buffer = Buffer::create(ctx, bytes, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, MemoryUsage::upload);
        if (!buffer.ok()) return buffer.error();
        u.buffers_.push_back(std::move(buffer).value());
        VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
        alloc.descriptorPool = pool;
        alloc.descriptorSetCount = 1;
        alloc.pSetLayouts = &layout;
        VkDescriptorSet set = VK_NULL_HANDLE;
        PBDSPLAT_VK_TRY(vkAllocateDescriptorSets(ctx.vk(), &alloc, &set));
        VkDescriptorBufferInfo info{u.buffers_.back().handle(), 0, bytes};
        VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        write.dstSet = set;
        write.descriptorCount = 1;
        write.descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
        write.pBufferInfo = &info;
        vkUpdateDescriptorSets(ctx.vk(), 1, &write, 0, nullptr);
        if (extra) write_extra(ctx, set, *extra, i);
        u.sets_.push_back(set);
    }
    return u;
}

void UniformSets::write_images(Context& ctx, uint32_t binding, std::span<const VkDescriptorImageInfo> images) const {
    std::vector<VkWriteDescriptorSet> writes;
    for (VkDescriptorSet set : sets_) {
        VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        w.dstSet = set;
        w.dstBinding = binding;
        w.descriptorCount = uint32_t(images.size());
        w.descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
        w.pImageInfo = images.data();
        writes.push_back(w);
    }
    if (!writes.empty()) vkUpdateDescriptorSets(ctx.vk(), uint32_t(writes.size()), writes.data(), 0, nullptr);
}

} // namespace pbdsplat::gpu
