#include "gpu/descriptor_pool.h"

namespace pbdsplat::gpu {

core::Result<DescriptorPool> create_descriptor_pool(const Context& ctx, VkDescriptorType type, uint32_t descriptors, uint32_t sets) {
    const VkDescriptorPoolSize size{type, descriptors};
    VkDescriptorPoolCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    info.maxSets = sets;
    info.poolSizeCount = 1;
    info.pPoolSizes = &size;
    VkDescriptorPool pool = VK_NULL_HANDLE;
    PBDSPLAT_VK_TRY(vkCreateDescriptorPool(ctx.vk(), &info, nullptr, &pool));
    return DescriptorPool(ctx.vk(), pool);
}

} // namespace pbdsplat::gpu
