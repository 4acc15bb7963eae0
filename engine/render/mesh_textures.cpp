#include "render/mesh_textures.h"

namespace pbdsplat::render {

core::Result<gpu::Texture> make_texture(gpu::Context& ctx, const MeshTexture& t) {
    return gpu::Texture::create_rgba8_srgb(ctx, t.width, t.height, t.rgba, t.wrap_u, t.wrap_v);
}

core::Result<gpu::Texture> make_white_texture(gpu::Context& ctx) {
    const uint8_t white[4] = {255, 255, 255, 255};
    return make_texture(ctx, {1, 1, white});
}

core::Result<MeshTextureSets> MeshTextureSets::create(gpu::Context& ctx) {
    MeshTextureSets s;
    auto texture = make_white_texture(ctx);
    if (!texture.ok()) return texture.error();
    s.white_ = std::move(texture).value();
    auto set = gpu::SampledImageSet::create(ctx, s.white_.view(), s.white_.sampler());
    if (!set.ok()) return set.error();
    s.white_set_ = std::move(set).value();
    return s;
}

core::Status MeshTextureSets::set(gpu::Context& ctx, std::span<const MeshTexture> textures) {
    textures_.clear();
    textures_.reserve(textures.size());
    for (const MeshTexture& t : textures) {
        auto texture = make_texture(ctx, t);
        if (!texture.ok()) return texture.error();
        auto set = gpu::SampledImageSet::create(ctx, texture->view(), texture->sampler());
        if (!set.ok()) return set.error();
        textures_.push_back({std::move(texture).value(), std::move(set).value()});
    }
    return core::Status::success();
}

VkDescriptorSet MeshTextureSets::set_of(int32_t texture) const {
    return texture >= 0 && size_t(texture) < textures_.size() ? textures_[size_t(texture)].set.set() : white_set_.set();
}

} // namespace pbdsplat::render
