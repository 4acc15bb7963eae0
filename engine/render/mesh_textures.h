#pragma once
// A model's colour textures as the lit mesh samples them, each in a descriptor set of its own
// (set 1 of the mesh raster's pipelines), and a white texel for what has none: the reference a
// textured model's splats are measured against reads the texture per pixel, as the asset is
// drawn, not from colours painted at its vertices.
#include <cstdint>
#include <span>
#include <vector>

#include "gpu/sampled_image_set.h"
#include "gpu/texture.h"

namespace pbdsplat::render {

// An asset's texture as files store it: sRGB-encoded RGBA bytes, rows top first.
struct MeshTexture {
    uint32_t width = 0, height = 0;
    std::span<const uint8_t> rgba;
    VkSamplerAddressMode wrap_u = VK_SAMPLER_ADDRESS_MODE_REPEAT, wrap_v = VK_SAMPLER_ADDRESS_MODE_REPEAT;
};

// The GPU image of a texture (sRGB-decoded when read, bilinear, its wrap modes), and a white
// texel for what has none.
core::Result<gpu::Texture> make_texture(gpu::Context& ctx, const MeshTexture& t);
core::Result<gpu::Texture> make_white_texture(gpu::Context& ctx);

class MeshTextureSets {
public:
    static core::Result<MeshTextureSets> create(gpu::Context& ctx);
    MeshTextureSets() = default;

    // Replaces the textures; call while no frame that reads them is in flight.
    core::Status set(gpu::Context& ctx, std::span<const MeshTexture> textures);
    // Every set's layout (one texture at binding 0, each set made alike).
    VkDescriptorSetLayout layout() const { return white_set_.layout(); }
    // Texture i's set, or the white texel's for -1 (or an index past the textures).
    VkDescriptorSet set_of(int32_t texture) const;
    size_t size() const { return textures_.size(); }

private:
    // The set refers to the texture's view and sampler: the two live and go together (the set
    // first).
    struct Entry {
        gpu::Texture texture;
        gpu::SampledImageSet set;
    };
    gpu::Texture white_;
    gpu::SampledImageSet white_set_;
    std::vector<Entry> textures_;
};

} // namespace pbdsplat::render
