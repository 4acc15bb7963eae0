#pragma once
// Per-frame uniform buffers, each bound to binding 0 of its own descriptor set: the shape every
// pass here uses for its FrameUniforms.
#include <vector>

#include "gpu/buffer.h"
#include "gpu/device_handle.h"

namespace pbdsplat::gpu {

// A set layout with one uniform buffer at binding 0, seen by `stages`.
core::Result<DescriptorSetLayout> create_uniform_layout(const Context& ctx, VkShaderStageFlags stages);

// The frame set of the splat passes: the uniforms at 0, a sampled texture at 1 and a storage
// buffer at 2 (the records, for the paths that pull them), each seen by its own stages; and,
// where `shapes`, `sh` and `order` name stages, more storage buffers at 3 (anisotropic splats'
// axes), 4 (view-dependent colour) and 5 (where each drawn splat's entries in 3 and 4 are).
struct FrameSetStages {
    VkShaderStageFlags uniforms = 0, texture = 0, storage = 0, shapes = 0, sh = 0, order = 0;
};
core::Result<DescriptorSetLayout> create_frame_layout(const Context& ctx, const FrameSetStages& stages);

// What bindings 1, 2 (and 3, 4, 5) of each frame set point at; storage[i] is set i's (one entry:
// all sets), the same for shapes, sh and order (empty: the layout has no such binding).
struct FrameSetResources {
    VkImageView texture_view = VK_NULL_HANDLE;
    VkSampler texture_sampler = VK_NULL_HANDLE;
    std::vector<VkBuffer> storage;
    std::vector<VkBuffer> shapes;
    std::vector<VkBuffer> sh;
    std::vector<VkBuffer> order;
};

class UniformSets {
public:
    // `count` host-visible buffers of `bytes` each, with a set per buffer.
    static core::Result<UniformSets> create(Context& ctx, VkDescriptorSetLayout layout, uint32_t count, VkDeviceSize bytes,
                                            const FrameSetResources* extra = nullptr);
    UniformSets() = default;

    VkDescriptorSet set(uint32_t i) const { return sets_[i]; }
    void* mapped(uint32_t i) const { return buffers_[i].mapped(); }

private:
    DescriptorPool pool_;
    std::vector<Buffer> buffers_;
    std::vector<VkDescriptorSet> sets_;
};

} // namespace pbdsplat::gpu
