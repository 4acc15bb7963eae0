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
    const VkDescriptorSetLayoutBinding bindings[4] = {
        {0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, stages.uniforms, nullptr},
        {1, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, stages.texture, nullptr},
        {2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, stages.storage, nullptr},
        {3, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, stages.shapes, nullptr}};
    VkDescriptorSetLayoutCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    info.bindingCount = stages.shapes ? 4 : 3;
    info.pBindings = bindings;
    VkDescriptorSetLayout layout = VK_NULL_HANDLE;
    PBDSPLAT_VK_TRY(vkCreateDescriptorSetLayout(ctx.vk(), &info, nullptr, &layout));
    return DescriptorSetLayout(ctx.vk(), layout);
}

core::Result<UniformSets> UniformSets::create(Context& ctx, VkDescriptorSetLayout layout, uint32_t count, VkDeviceSize bytes,
                                              const FrameSetResources* extra) {
    UniformSets u;
    const VkDescriptorPoolSize sizes[3] = {{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, count},
                                           {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, count},
                                           {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 2 * count}};
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
        if (extra) {
            VkDescriptorImageInfo image{extra->texture_sampler, extra->texture_view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
            VkDescriptorBufferInfo storage{extra->storage.size() > 1 ? extra->storage[i] : extra->storage.front(), 0, VK_WHOLE_SIZE};
            const bool shapes = !extra->shapes.empty();
            VkDescriptorBufferInfo shape_info{shapes ? (extra->shapes.size() > 1 ? extra->shapes[i] : extra->shapes.front()) : VK_NULL_HANDLE,
                                              0, VK_WHOLE_SIZE};
            VkWriteDescriptorSet more[3] = {{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET}, {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET},
                                            {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET}};
            more[0].dstSet = more[1].dstSet = more[2].dstSet = set;
            more[0].dstBinding = 1;
            more[0].descriptorCount = 1;
            more[0].descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
            more[0].pImageInfo = &image;
            more[1].dstBinding = 2;
            more[1].descriptorCount = 1;
            more[1].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
            more[1].pBufferInfo = &storage;
            more[2].dstBinding = 3;
            more[2].descriptorCount = 1;
            more[2].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
            more[2].pBufferInfo = &shape_info;
            vkUpdateDescriptorSets(ctx.vk(), shapes ? 3 : 2, more, 0, nullptr);
        }
        u.sets_.push_back(set);
    }
    return u;
}

} // namespace pbdsplat::gpu
