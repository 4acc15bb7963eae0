#pragma once
// A sampled 2D texture filled once at creation (an environment map, a model's colour texture):
// the copy runs on its own one-shot command buffer and is waited for, so no frame ever sees it
// half written. Sampled bilinearly without mip levels.
#include <functional>
#include <span>

#include "gpu/image.h"

namespace pbdsplat::gpu {

class Texture {
public:
    Texture() = default;
    // `texels`: width * height RGBA float texels, stored as RGBA16F, sampled linearly with
    // repeat in u (longitude) and clamp in v.
    static core::Result<Texture> create_rgba16f(Context& ctx, uint32_t width, uint32_t height, std::span<const float> texels);
    // `texels`: width * height sRGB-encoded RGBA bytes, rows first to last; read back linear.
    static core::Result<Texture> create_rgba8_srgb(Context& ctx, uint32_t width, uint32_t height, std::span<const uint8_t> texels,
                                                   VkSamplerAddressMode wrap_u, VkSamplerAddressMode wrap_v);

    VkImageView view() const { return image_.view(); }
    VkSampler sampler() const { return sampler_.get(); }

private:
    static core::Result<Texture> create(Context& ctx, uint32_t width, uint32_t height, VkFormat format, std::span<const std::byte> bytes,
                                        VkSamplerAddressMode wrap_u, VkSamplerAddressMode wrap_v);
    Image image_;
    Sampler sampler_;
};

// Records `record` into a fresh command buffer, submits it and waits: for creation-time work.
core::Status submit_once(Context& ctx, const std::function<void(VkCommandBuffer)>& record);

} // namespace pbdsplat::gpu
