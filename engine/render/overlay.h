#pragma once
// The windowed demo's overlay: an RGBA8 image (premultiplied alpha) that the CPU draws text and
// strokes into, copied to the GPU each frame and blended over the presented image. Its two
// steps are separate graph passes, so the graph places the image's barriers.
#include <memory>
#include <vector>

#include "core/image.h"
#include "gpu/buffer.h"
#include "gpu/device_handle.h"
#include "gpu/image.h"
#include "gpu/sampled_image_set.h"
#include "gpu/texture.h"
#include "render/splat_renderer.h"

namespace pbdsplat::render {

namespace uses {
inline constexpr Use overlay_sampled{{VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT},
                                     VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
inline constexpr Use copy_destination{{VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT},
                                      VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL};
} // namespace uses

class OverlayPass {
public:
    // `target_format`: the format of the images it is drawn over (the swapchain's).
    static core::Result<std::unique_ptr<OverlayPass>> create(gpu::Context& ctx, uint32_t width, uint32_t height,
                                                             VkFormat target_format, uint32_t slots);

    // The overlay frames from now on show (same size as created). Cheap when unchanged.
    void set(const core::ImageRgba8& image);
    // Copies the newest overlay into the image (in TRANSFER_DST layout).
    void record_upload(VkCommandBuffer cmd, uint32_t slot);
    // Blends the overlay over `target` (in COLOR_ATTACHMENT layout).
    void record_draw(VkCommandBuffer cmd, VkImageView target, VkExtent2D extent) const;

    VkImage image() const { return image_.handle(); }
    uint32_t width() const { return image_.width(); }
    uint32_t height() const { return image_.height(); }

private:
    OverlayPass() = default;
    gpu::Image image_;
    std::vector<gpu::Buffer> staging_;       // per slot
    std::vector<uint64_t> staged_version_;   // what each slot's staging buffer holds
    core::ImageRgba8 latest_;
    uint64_t version_ = 0;
    gpu::SampledImageSet set_;
    gpu::PipelineLayout layout_;
    gpu::Pipeline pipeline_;
};

} // namespace pbdsplat::render
