#pragma once
// The colour + depth images a frame renders into when there is no window, and the per-frame
// buffers that carry the colour image back to the CPU.
#include <vector>

#include "core/image.h"
#include "gpu/buffer.h"
#include "gpu/image.h"

namespace pbdsplat::render {

constexpr VkFormat k_color_format = VK_FORMAT_R8G8B8A8_UNORM;
constexpr VkFormat k_depth_format = VK_FORMAT_D32_SFLOAT;

class OffscreenTarget {
public:
    static core::Result<OffscreenTarget> create(gpu::Context& ctx, uint32_t width, uint32_t height,
                                                uint32_t frames_in_flight);
    OffscreenTarget() = default;

    uint32_t width() const { return color_.width(); }
    uint32_t height() const { return color_.height(); }
    const gpu::Image& color() const { return color_; }
    const gpu::Image& depth() const { return depth_; }

    // Begins dynamic rendering with a clear; the images must be in the attachment layouts
    // (the frame graph's barriers put them there: see color_use / depth_use).
    // `keep_depth`: store the depth for a later pass (normalised blending's accumulation).
    void begin(VkCommandBuffer cmd, const float clear_rgba[4], bool keep_depth = false);
    // Goes on drawing into what an earlier pass of the frame left (colour and depth loaded).
    void resume(VkCommandBuffer cmd);
    void end(VkCommandBuffer cmd);
    // Copies the colour image (in TRANSFER_SRC layout) into the readback buffer of `slot`, and
    // makes the copy visible to the host once the frame's fence signals.
    void record_readback(VkCommandBuffer cmd, uint32_t slot);
    VkBuffer readback_buffer(uint32_t slot) const { return readback_[slot].handle(); }
    // The image copied by the frame in `slot`; valid once that frame's fence has signalled.
    core::ImageRgba8 read(uint32_t slot) const;

private:
    gpu::Image color_;
    gpu::Image depth_;
    std::vector<gpu::Buffer> readback_;
};

} // namespace pbdsplat::render
