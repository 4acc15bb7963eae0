#pragma once
// Per-frame uniform buffers, each bound to binding 0 of its own descriptor set: the shape every
// pass here uses for its FrameUniforms.
#include <span>
#include <vector>

#include "gpu/buffer.h"
#include "gpu/device_handle.h"

namespace pbdsplat::gpu {

// A set layout with one uniform buffer at binding 0, seen by `stages`.
core::Result<DescriptorSetLayout> create_uniform_layout(const Context& ctx, VkShaderStageFlags stages);

// The frame set of the splat passes: the uniforms at 0, a sampled texture at 1 and a storage
// buffer at 2 (the records, for the paths that pull them), each seen by its own stages; and,
// where `shapes`, `sh`, `order` and `texcoords` name stages, more storage buffers at 3
// (anisotropic splats' axes), 4 (view-dependent colour), 5 (where each drawn splat's entries in
// the streams are) and 6 (textured splats' coordinates); where `textures` does, an array of
// `texture_count` sampled textures at 7 (a textured model's).
struct FrameSetStages {
    VkShaderStageFlags uniforms = 0, texture = 0, storage = 0, shapes = 0, sh = 0, order = 0, texcoords = 0, textures = 0;
    uint32_t texture_count = 0;
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
    std::vector<VkBuffer> texcoords;
    std::vector<VkDescriptorImageInfo> textures;  // binding 7's array, whole
};

class UniformSets {
public:
    // `count` host-visible buffers of `bytes` each, with a set per buffer.
    static core::Result<UniformSets> create(Context& ctx, VkDescriptorSetLayout layout, uint32_t count, VkDeviceSize bytes,
                                            const FrameSetResources* extra = nullptr);
    UniformSets() = default;

    VkDescriptorSet set(uint32_t i) const { return sets_[i]; }
    size_t size() const { return sets_.size(); }
    // Points every set's array of textures at `binding` at `images`; only while no frame that
    // reads the sets is in flight.
    void write_images(Context& ctx, uint32_t binding, std::span<const VkDescriptorImageInfo> images) const;
    void* mapped(uint32_t i) const { return buffers_[i].mapped(); }

private:
    DescriptorPool pool_;
    std::vector<Buffer> buffers_;
    std::vector<VkDescriptorSet> sets_;
};

} // namespace pbdsplat::gpu
