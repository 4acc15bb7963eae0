#include "render/environment_texture.h"

namespace pbdsplat::render {

core::Result<EnvironmentTexture> make_environment_texture(gpu::Context& ctx, const std::string& map_path, const Vec3f& sun) {
    core::Result<EnvironmentMap> map = core::make_error("no environment");
    if (map_path.empty() || map_path == std::string(k_procedural_prefix) + "sky") map = procedural_sky(sun);
    else if (map_path == std::string(k_procedural_prefix) + "studio") map = procedural_studio(sun);
    else map = load_environment_map(map_path);
    if (!map.ok()) return map.error();
    EnvironmentTexture e;
    e.sh = irradiance_sh(map.value());
    auto texture = gpu::Texture::create_rgba16f(ctx, map->width, map->height, map->rgba);
    if (!texture.ok()) return texture.error();
    e.texture = std::move(texture).value();
    return e;
}

} // namespace pbdsplat::render
