#pragma once
// A descriptor set with images at bindings 0, 1, ... (each combined with one nearest, clamped
// sampler, or the sampler given) for a fragment shader (or the stages given) that reads images another pass wrote or
// uploaded: texel for texel, or filtered as a texture's own sampler says.
#include <span>

#include "gpu/context.h"
#include "gpu/device_handle.h"

namespace pbdsplat::gpu {

class SampledImageSet {
public:
    // `view` is read in SHADER_READ_ONLY_OPTIMAL layout.
    static core::Result<SampledImageSet> create(const Context& ctx, VkImageView view);
    // `views[i]` at binding i, each read in SHADER_READ_ONLY_OPTIMAL layout by `stages`.
    static core::Result<SampledImageSet> create(const Context& ctx, std::span<const VkImageView> views,
                                                VkShaderStageFlags stages = VK_SHADER_STAGE_FRAGMENT_BIT);
    // `view` at binding 0 with `sampler` (which must outlive the set), e.g. a gpu::Texture's.
    static core::Result<SampledImageSet> create(const Context& ctx, VkImageView view, VkSampler sampler);
    SampledImageSet() = default;

    VkDescriptorSetLayout layout() const { return layout_.get(); }
    VkDescriptorSet set() const { return set_; }

private:
    static core::Result<SampledImageSet> create_with(const Context& ctx, std::span<const VkImageView> views, VkSampler sampler,
                                                     VkShaderStageFlags stages = VK_SHADER_STAGE_FRAGMENT_BIT);
    Sampler sampler_;  // the set's own, when no sampler was given
    DescriptorSetLayout layout_;
    DescriptorPool pool_;
    VkDescriptorSet set_ = VK_NULL_HANDLE;  // freed with the pool
};

} // namespace pbdsplat::gpu
