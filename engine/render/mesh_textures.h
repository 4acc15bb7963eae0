#pragma once
// A model's colour textures as the lit mesh samples them, each in a descriptor set of its own
// (set 1 of the mesh raster's pipelines), and a white texel for what has none: the reference a
// textured model's splats are measured against reads the texture per pixel, as the asset is
// drawn, not from colours painted at its vertices.
#include <cstdint>
#include <span>
#include <vector>

#include "gpu/device_handle.h"
#include "gpu/texture.h"

namespace pbdsplat::render {

// An asset's texture as files store it: sRGB-encoded RGBA bytes, rows top first.
struct MeshTexture {
    uint32_t width = 0, height = 0;
    std::span<const uint8_t> rgba;
    VkSamplerAddressMode wrap_u = VK_SAMPLER_ADDRESS_MODE_REPEAT, wrap_v = VK_SAMPLER_ADDRESS_MODE_REPEAT;
};

class MeshTextureSets {
public:
    static core::Result<MeshTextureSets> create(gpu::Context& ctx);
    MeshTextureSets() = default;

    // Replaces the textures; call while no frame that reads them is in flight.
    core::Status set(gpu::Context& ctx, std::span<const MeshTexture> textures);
    VkDescriptorSetLayout layout() const { return layout_.get(); }
    // Texture i's set, or the white texel's for -1 (or an index past the textures).
    VkDescriptorSet set_of(int32_t texture) const;
    size_t size() const { return textures_.size(); }

private:
    static core::Result<VkDescriptorSet> make_set(gpu::Context& ctx, const gpu::DescriptorPool& pool, VkDescriptorSetLayout layout,
                                                  const gpu::Texture& texture);
    gpu::DescriptorSetLayout layout_;
    gpu::Texture white_;
    gpu::DescriptorPool white_pool_;
    VkDescriptorSet white_set_ = VK_NULL_HANDLE;  // freed with its pool
    std::vector<gpu::Texture> textures_;
    gpu::DescriptorPool pool_;
    std::vector<VkDescriptorSet> sets_;
};

} // namespace pbdsplat::render
