#pragma once
// The splat pass, geometry-shader path: one point per Gaussian record in, one masked and
// shaded quad out (paper sections 5.5-5.6).
#include "gpu/device_handle.h"
#include "gpu/pipeline.h"
#include "render/frame_inputs.h"

namespace pbdsplat::render {

class SplatPass {
public:
    // Fails with a clear reason on a device without geometry shaders.
    static core::Result<SplatPass> create(const gpu::Context& ctx, VkFormat color, VkFormat depth);
    SplatPass() = default;

    VkDescriptorSetLayout set_layout() const { return set_layout_.get(); }
    void record(VkCommandBuffer cmd, Blend blend, VkDescriptorSet frame_set, VkBuffer records, uint32_t count) const;

private:
    gpu::DescriptorSetLayout set_layout_;
    gpu::PipelineLayout layout_;
    gpu::Pipeline visibility_;
    gpu::Pipeline over_;
    gpu::Pipeline additive_;
};

} // namespace pbdsplat::render
