#pragma once
// A descriptor set with one image at binding 0 (combined with a nearest, clamped sampler) for a
// fragment shader that reads an image another pass wrote or uploaded, texel for texel.
#include "gpu/context.h"
#include "gpu/device_handle.h"

namespace pbdsplat::gpu {

class SampledImageSet {
public:
    // `view` is read in SHADER_READ_ONLY_OPTIMAL layout.
    static core::Result<SampledImageSet> create(const Context& ctx, VkImageView view);
    SampledImageSet() = default;

    VkDescriptorSetLayout layout() const { return layout_.get(); }
    VkDescriptorSet set() const { return set_; }

private:
    Sampler sampler_;
    DescriptorSetLayout layout_;
    DescriptorPool pool_;
    VkDescriptorSet set_ = VK_NULL_HANDLE;  // freed with the pool
};

} // namespace pbdsplat::gpu
