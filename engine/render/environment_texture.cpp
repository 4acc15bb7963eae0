#include "render/environment_texture.h"

namespace pbdsplat::render {

core::Result<EnvironmentTexture> make_environment_texture(gpu::Context& ctx, const std::string& map_path, const Vec3f& sun) {
    auto map = make_environment_map(map_path, sun);
    if (!map.ok()) return map.error();
    EnvironmentTexture e;
    e.sh = irradiance_sh(map.value());
    auto texture = gpu::Texture::create_rgba16f(ctx, map->width, map->height, map->rgba);
    if (!texture.ok()) return texture.error();
    e.texture = std::move(texture).value();
    return e;
}

} // namespace pbdsplat::render
