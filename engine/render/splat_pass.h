#pragma once
// The splat pass: one masked and shaded quad per Gaussian record (paper sections 5.4-5.6), by
// one of three interchangeable paths that draw the same quads (shaders/shared/
// splat_footprint.glsl): a geometry shader expanding points, a mesh shader expanding a fixed
// number of splats per workgroup, or vertex pulling (six vertices per splat) for devices with
// neither.
#include <optional>

#include "gpu/device_handle.h"
#include "gpu/pipeline.h"
#include "render/frame_inputs.h"

namespace pbdsplat::render {

enum class SplatPath { geometry, mesh, vertex };
const char* splat_path_name(SplatPath p);
// The best path the device has: mesh, then geometry, then vertex pulling.
SplatPath best_splat_path(const gpu::DeviceCaps& caps);
// Why the device cannot run `path` (empty when it can).
std::string splat_path_unsupported(const gpu::DeviceCaps& caps, SplatPath path);

// The splats one draw reads: `count` records, or, after a GPU sort, as many as its control
// block says (`indirect`, SORT_CONTROL_* in gpu_types.h) out of at most `count`.
struct SplatSource {
    VkBuffer records = VK_NULL_HANDLE;
    uint32_t count = 0;
    VkBuffer indirect = VK_NULL_HANDLE;
};

class SplatPass {
public:
    // Fails with a clear reason when the device lacks what the path needs.
    static core::Result<SplatPass> create(const gpu::Context& ctx, VkFormat color, VkFormat depth, SplatPath path,
                                          SplatShading shading = SplatShading::fragment);
    SplatPass() = default;

    SplatPath path() const { return path_; }
    SplatShading shading() const { return shading_; }
    VkDescriptorSetLayout set_layout() const { return set_layout_.get(); }
    // Unsorted "over" draws the visibility pass first; sorted orders and additive blending
    // draw the colour pass alone. `frame_set`'s storage binding must hold `source.records`.
    void record(VkCommandBuffer cmd, Blend blend, SplatOrder order, VkDescriptorSet frame_set, const SplatSource& source) const;

private:
    SplatPath path_ = SplatPath::geometry;
    SplatShading shading_ = SplatShading::fragment;
    gpu::DescriptorSetLayout set_layout_;
    gpu::PipelineLayout layout_;
    gpu::Pipeline visibility_;
    gpu::Pipeline over_;
    gpu::Pipeline additive_;
    PFN_vkCmdDrawMeshTasksEXT draw_mesh_tasks_ = nullptr;
    PFN_vkCmdDrawMeshTasksIndirectEXT draw_mesh_tasks_indirect_ = nullptr;
    void draw(VkCommandBuffer cmd, const SplatSource& source) const;
};

} // namespace pbdsplat::render
