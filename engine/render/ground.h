#pragma once
// The scene's ground plane, drawn into the splat target before the splats: a shaded disc on the
// plane collider with a contact shadow under the body (render.ground).
#include "gpu/device_handle.h"
#include "gpu/pipeline.h"
#include "render/frame_inputs.h"

namespace pbdsplat::render {

class GroundPass {
public:
    // `frame_layout`: the splat pass's set layout (the uniforms at binding 0).
    static core::Result<GroundPass> create(const gpu::Context& ctx, VkFormat color, VkFormat depth, VkDescriptorSetLayout frame_layout);
    GroundPass() = default;
    // Inside the splat target's rendering, before the splats.
    void record(VkCommandBuffer cmd, VkDescriptorSet frame_set, const Ground& ground) const;

private:
    gpu::PipelineLayout layout_;
    gpu::Pipeline pipeline_;
};

} // namespace pbdsplat::render
