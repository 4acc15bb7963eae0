#pragma once
// Normalised blending (render.blend = "normalised"): the front surface's splats are averaged
// instead of composited one over another. The splat pass lays down the visibility depth, an
// accumulation pass adds every front fragment's weighted colour and weight into a float image,
// and the resolve here divides and blends the result over the colour target. With the Gaussian
// footprint's smooth weights the colour at a pixel varies continuously as discs begin and end,
// so no disc's rim shows (surface splatting's normalisation). The two steps are separate graph
// passes, so the graph places the accumulation images' barriers.
//
// Two layers are summed apart: splats seen from the side they face (the outer surface) and
// splats seen from behind (an open body's inside, through an opening or between the outer
// surface's splats). Where the visibility pass's opaque cores leave a gap between the outer
// surface's splats, the inside behind it passes the depth test there too; averaged together, its
// heavier weights drew the inside's colour as a dark dot. The resolve lets the outer layer's
// colour win wherever it reaches and gives the inside the rest.
#include "gpu/device_handle.h"
#include "gpu/image.h"
#include "gpu/sampled_image_set.h"
#include "render/gpu_use.h"

namespace pbdsplat::render {

// Sums of w c (rgb) and w (a), w = -ln(1 - alpha): 16-bit floats hold a few hundred splats of
// weight 5.5 (alpha 0.996) and their colours.
constexpr VkFormat k_accumulation_format = VK_FORMAT_R16G16B16A16_SFLOAT;
// The accumulation's layers, one image each: fragment outputs 0 and 1 (splat_fragment.glsl).
enum class SumLayer : uint32_t { seen_side = 0, inside = 1 };
constexpr uint32_t k_sum_layers = 2;

namespace uses {
inline constexpr Use accumulation_sampled{{VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_READ_BIT},
                                          VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
} // namespace uses

class NormalisedBlend {
public:
    // `target_format`: the colour target the resolve blends over.
    static core::Result<NormalisedBlend> create(gpu::Context& ctx, uint32_t width, uint32_t height, VkFormat target_format);
    NormalisedBlend() = default;

    const gpu::Image& accumulation(SumLayer layer) const { return layers_[uint32_t(layer)]; }
    // Begins rendering into the accumulation images (cleared to zero) with `depth` attached for
    // testing (loaded; the accumulation pipeline does not write it, but an attachment's store
    // counts as a write: the graph sees a depth attachment use). Both in attachment layouts.
    // `area`: the pixels the splats can reach (render/screen_bounds.h); only they are cleared,
    // summed and, given the same area, resolved.
    void begin_accumulation(VkCommandBuffer cmd, VkImageView depth, VkRect2D area) const;
    void end_accumulation(VkCommandBuffer cmd) const;
    // Divides the sums and blends them over `target` (COLOR_ATTACHMENT layout); the accumulation
    // images must be in SHADER_READ_ONLY layout.
    void record_resolve(VkCommandBuffer cmd, VkImageView target, VkRect2D area) const;

private:
    gpu::Image layers_[k_sum_layers];
    gpu::SampledImageSet sums_;  // the accumulation images, for the resolve
    gpu::PipelineLayout layout_;
    gpu::Pipeline resolve_;
    VkExtent2D extent_{};
};

} // namespace pbdsplat::render
