#pragma once
// The splat pass's lighting (shaders/shared/shading.glsl: eqs. 24-25, the key light, the extra
// lights) evaluated on the CPU, for colours baked into exported files that viewers without the
// paper's lighting show as they looked here. The environment's specular lookup takes the
// nearest texel where the GPU filters: the two differ by a fraction of a texel's change.
#include <array>
#include <cstdint>

#include "render/environment.h"
#include "render/frame_inputs.h"

namespace pbdsplat::render {

struct CpuShading {
    const Lighting* lighting = nullptr;
    const EnvironmentMap* map = nullptr;  // null: the environment terms are black
    std::array<Vec3f, 9> sh{};            // the map's irradiance (irradiance_sh)
    Vec3f eye = Vec3f::Zero();
    bool opaque_discs = true;  // the paper's footprint; false: soft Gaussians (see splat_lit_normal)
};

// The lit colour of a surface point of `albedo` with unit normal `n` at `world`, seen from eye
// (a normal facing away from the eye is lit as the splat pass lights it: `opaque_discs`), of
// `model` (its position-based lookups look out from that model's centre, as the shaders' do).
Vec3f shade_cpu(const CpuShading& s, const Vec3f& albedo, const Vec3f& n, const Vec3f& world, uint32_t model = 0);

} // namespace pbdsplat::render
