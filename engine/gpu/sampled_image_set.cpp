#include "gpu/sampled_image_set.h"

#include "gpu/descriptor_pool.h"

#include <vector>

namespace pbdsplat::gpu {

core::Result<SampledImageSet> SampledImageSet::create(const Context& ctx, VkImageView view) {
    return create(ctx, std::span<const VkImageView>(&view, 1));
}

core::Result<SampledImageSet> SampledImageSet::create(const Context& ctx, std::span<const VkImageView> views, VkShaderStageFlags stages) {
    VkSamplerCreateInfo sampler_info{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    sampler_info.magFilter = sampler_info.minFilter = VK_FILTER_NEAREST;  // one texel per pixel
    sampler_info.addressModeU = sampler_info.addressModeV = sampler_info.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    VkSampler sampler = VK_NULL_HANDLE;
    PBDSPLAT_VK_TRY(vkCreateSampler(ctx.vk(), &sampler_info, nullptr, &sampler));
    Sampler owned(ctx.vk(), sampler);
    auto s = create_with(ctx, views, sampler, stages);
    if (s.ok()) s->sampler_ = std::move(owned);
    return s;
}

core::Result<SampledImageSet> SampledImageSet::create(const Context& ctx, VkImageView view, VkSampler sampler) {
    return create_with(ctx, std::span<const VkImageView>(&view, 1), sampler);
}

core::Result<SampledImageSet> SampledImageSet::create_with(const Context& ctx, std::span<const VkImageView> views, VkSampler sampler,
                                                          VkShaderStageFlags stages) {
    SampledImageSet s;
    const uint32_t n = uint32_t(views.size());

    std::vector<VkDescriptorSetLayoutBinding> bindings;
    for (uint32_t i = 0; i < n; ++i) bindings.push_back({i, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, stages, nullptr});
    VkDescriptorSetLayoutCreateInfo layout_info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    layout_info.bindingCount = n;
    layout_info.pBindings = bindings.data();
    VkDescriptorSetLayout layout = VK_NULL_HANDLE;
    PBDSPLAT_VK_TRY(vkCreateDescriptorSetLayout(ctx.vk(), &layout_info, nullptr, &layout));
    s.layout_ = DescriptorSetLayout(ctx.vk(), layout);

    auto pool_made = create_descriptor_pool(ctx, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, n, 1);
    if (!pool_made.ok()) return pool_made.error();
    s.pool_ = std::move(pool_made).value();
    const VkDescriptorPool pool = s.pool_.get();

    VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    alloc.descriptorPool = pool;
    alloc.descriptorSetCount = 1;
    alloc.pSetLayouts = &layout;
    PBDSPLAT_VK_TRY(vkAllocateDescriptorSets(ctx.vk(), &alloc, &s.set_));
    std::vector<VkDescriptorImageInfo> images;
    for (VkImageView view : views) images.push_back({sampler, view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL});
    std::vector<VkWriteDescriptorSet> writes(n, VkWriteDescriptorSet{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET});
    for (uint32_t i = 0; i < n; ++i) {
        writes[i].dstSet = s.set_;
        writes[i].dstBinding = i;
        writes[i].descriptorCount = 1;
        writes[i].descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
        writes[i].pImageInfo = &images[i];
    }
    vkUpdateDescriptorSets(ctx.vk(), n, writes.data(), 0, nullptr);
    return s;
}

} // namespace pbdsplat::gpu
