#include "gpu/sampled_image_set.h"

namespace pbdsplat::gpu {

core::Result<SampledImageSet> SampledImageSet::create(const Context& ctx, VkImageView view) {
    SampledImageSet s;
    VkSamplerCreateInfo sampler_info{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    sampler_info.magFilter = sampler_info.minFilter = VK_FILTER_NEAREST;  // one texel per pixel
    sampler_info.addressModeU = sampler_info.addressModeV = sampler_info.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    VkSampler sampler = VK_NULL_HANDLE;
    PBDSPLAT_VK_TRY(vkCreateSampler(ctx.vk(), &sampler_info, nullptr, &sampler));
    s.sampler_ = Sampler(ctx.vk(), sampler);

    const VkDescriptorSetLayoutBinding binding{0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr};
    VkDescriptorSetLayoutCreateInfo layout_info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    layout_info.bindingCount = 1;
    layout_info.pBindings = &binding;
    VkDescriptorSetLayout layout = VK_NULL_HANDLE;
    PBDSPLAT_VK_TRY(vkCreateDescriptorSetLayout(ctx.vk(), &layout_info, nullptr, &layout));
    s.layout_ = DescriptorSetLayout(ctx.vk(), layout);

    const VkDescriptorPoolSize pool_size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1};
    VkDescriptorPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    pool_info.maxSets = 1;
    pool_info.poolSizeCount = 1;
    pool_info.pPoolSizes = &pool_size;
    VkDescriptorPool pool = VK_NULL_HANDLE;
    PBDSPLAT_VK_TRY(vkCreateDescriptorPool(ctx.vk(), &pool_info, nullptr, &pool));
    s.pool_ = DescriptorPool(ctx.vk(), pool);

    VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    alloc.descriptorPool = pool;
    alloc.descriptorSetCount = 1;
    alloc.pSetLayouts = &layout;
    PBDSPLAT_VK_TRY(vkAllocateDescriptorSets(ctx.vk(), &alloc, &s.set_));
    const VkDescriptorImageInfo image{sampler, view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
    VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    write.dstSet = s.set_;
    write.descriptorCount = 1;
    write.descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    write.pImageInfo = &image;
    vkUpdateDescriptorSets(ctx.vk(), 1, &write, 0, nullptr);
    return s;
}

} // namespace pbdsplat::gpu
