#pragma once
// Rasterises the deformed simulation mesh into a mask (and depth): the reference the splats'
// coverage is measured against (hole ratio, silhouette IoU). Not part of a normal frame.
#include <array>
#include <memory>
#include <span>

#include "core/image.h"
#include "gpu/buffer.h"
#include "gpu/device_handle.h"
#include "gpu/pipeline.h"
#include "gpu/uniform_sets.h"
#include "render/frame_inputs.h"
#include "render/offscreen_target.h"
#include "render/splat_renderer.h"

namespace pbdsplat::render {

class MeshRaster {
public:
    static core::Result<std::unique_ptr<MeshRaster>> create(gpu::Context& ctx, uint32_t width, uint32_t height,
                                                            size_t max_vertices, size_t max_triangles);

    // Copies the mesh into the (host-visible) vertex and index buffers; call while no frame
    // using them is in flight.
    core::Status set_mesh(std::span<const Vec4f> positions, std::span<const std::array<uint32_t, 3>> triangles);
    // Draws into the target (in attachment layouts), then copies the colour image out (the
    // caller's frame graph places the barriers: uses::color_attachment etc.).
    void draw(VkCommandBuffer cmd, const FrameInputs& inputs);
    void readback(VkCommandBuffer cmd) { target_.record_readback(cmd, 0); }
    core::ImageRgba8 read() const { return target_.read(0); }

    VkImage color_image() const { return target_.color().handle(); }
    VkImage depth_image() const { return target_.depth().handle(); }
    VkBuffer readback_buffer() const { return target_.readback_buffer(0); }

private:
    MeshRaster() = default;
    gpu::Context* ctx_ = nullptr;
    OffscreenTarget target_;
    gpu::Buffer vertices_, indices_;
    uint32_t index_count_ = 0;
    gpu::DescriptorSetLayout set_layout_;
    gpu::UniformSets uniforms_;
    gpu::PipelineLayout layout_;
    gpu::Pipeline pipeline_;
};

} // namespace pbdsplat::render
