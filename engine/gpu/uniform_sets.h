#pragma once
// Per-frame uniform buffers, each bound to binding 0 of its own descriptor set: the shape every
// pass here uses for its FrameUniforms.
#include <vector>

#include "gpu/buffer.h"
#include "gpu/device_handle.h"

namespace pbdsplat::gpu {

// A set layout with one uniform buffer at binding 0, seen by `stages`.
core::Result<DescriptorSetLayout> create_uniform_layout(const Context& ctx, VkShaderStageFlags stages);

class UniformSets {
public:
    // `count` host-visible buffers of `bytes` each, with a set per buffer.
    static core::Result<UniformSets> create(Context& ctx, VkDescriptorSetLayout layout, uint32_t count, VkDeviceSize bytes);
    UniformSets() = default;

    VkDescriptorSet set(uint32_t i) const { return sets_[i]; }
    void* mapped(uint32_t i) const { return buffers_[i].mapped(); }

private:
    DescriptorPool pool_;
    std::vector<Buffer> buffers_;
    std::vector<VkDescriptorSet> sets_;
};

} // namespace pbdsplat::gpu
