#include "render/mesh_textures.h"

#include "gpu/descriptor_pool.h"

namespace pbdsplat::render {

core::Result<MeshTextureSets> MeshTextureSets::create(gpu::Context& ctx) {
    MeshTextureSets s;
    const VkDescriptorSetLayoutBinding binding{0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr};
    VkDescriptorSetLayoutCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    info.bindingCount = 1;
    info.pBindings = &binding;
    VkDescriptorSetLayout layout = VK_NULL_HANDLE;
    PBDSPLAT_VK_TRY(vkCreateDescriptorSetLayout(ctx.vk(), &info, nullptr, &layout));
    s.layout_ = gpu::DescriptorSetLayout(ctx.vk(), layout);
    const uint8_t white[4] = {255, 255, 255, 255};
    auto texture = gpu::Texture::create_rgba8_srgb(ctx, 1, 1, white, VK_SAMPLER_ADDRESS_MODE_REPEAT, VK_SAMPLER_ADDRESS_MODE_REPEAT);
    if (!texture.ok()) return texture.error();
    s.white_ = std::move(texture).value();
    auto pool = gpu::create_descriptor_pool(ctx, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, 1);
    if (!pool.ok()) return pool.error();
    s.white_pool_ = std::move(pool).value();
    auto set = make_set(ctx, s.white_pool_, layout, s.white_);
    if (!set.ok()) return set.error();
    s.white_set_ = set.value();
    return s;
}

core::Status MeshTextureSets::set(gpu::Context& ctx, std::span<const MeshTexture> textures) {
    sets_.clear();
    pool_ = {};
    textures_.clear();
    if (textures.empty()) return core::Status::success();
    for (const MeshTexture& t : textures) {
        auto texture = gpu::Texture::create_rgba8_srgb(ctx, t.width, t.height, t.rgba, t.wrap_u, t.wrap_v);
        if (!texture.ok()) return texture.error();
        textures_.push_back(std::move(texture).value());
    }
    auto pool = gpu::create_descriptor_pool(ctx, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, uint32_t(textures_.size()),
                                            uint32_t(textures_.size()));
    if (!pool.ok()) return pool.error();
    pool_ = std::move(pool).value();
    for (const gpu::Texture& t : textures_) {
        auto set = make_set(ctx, pool_, layout_.get(), t);
        if (!set.ok()) return set.error();
        sets_.push_back(set.value());
    }
    return core::Status::success();
}

VkDescriptorSet MeshTextureSets::set_of(int32_t texture) const {
    return texture >= 0 && size_t(texture) < sets_.size() ? sets_[size_t(texture)] : white_set_;
}

core::Result<VkDescriptorSet> MeshTextureSets::make_set(gpu::Context& ctx, const gpu::DescriptorPool& pool, VkDescriptorSetLayout layout,
                                                        const gpu::Texture& texture) {
    VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    alloc.descriptorPool = pool.get();
    alloc.descriptorSetCount = 1;
    alloc.pSetLayouts = &layout;
    VkDescriptorSet set = VK_NULL_HANDLE;
    PBDSPLAT_VK_TRY(vkAllocateDescriptorSets(ctx.vk(), &alloc, &set));
    const VkDescriptorImageInfo image{texture.sampler(), texture.view(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
    VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    write.dstSet = set;
    write.dstBinding = 0;
    write.descriptorCount = 1;
    write.descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    write.pImageInfo = &image;
    vkUpdateDescriptorSets(ctx.vk(), 1, &write, 0, nullptr);
    return set;
}

} // namespace pbdsplat::render
