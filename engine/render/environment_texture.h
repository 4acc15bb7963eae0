#pragma once
// The environment as the GPU passes read it: the radiance map as a texture and its irradiance
// coefficients, made once from a file or the procedural sky.
#include <array>
#include <string>

#include "gpu/texture.h"
#include "render/environment.h"

namespace pbdsplat::render {

struct EnvironmentTexture {
    gpu::Texture texture;
    std::array<Vec3f, 9> sh{};
};

// `map_path` empty or "procedural:sky": the procedural sky lit from `sun`; "procedural:studio":
// the studio; anything else: a PNG or .hdr file.
core::Result<EnvironmentTexture> make_environment_texture(gpu::Context& ctx, const std::string& map_path, const Vec3f& sun);

} // namespace pbdsplat::render
