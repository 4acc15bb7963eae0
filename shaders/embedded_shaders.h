#pragma once
// The SPIR-V compiled from shaders/*.{vert,geom,frag,comp,mesh} at build time.
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

namespace pbdsplat::shaders {
// Words of the named shader ("splat.geom"), or an empty span when no such shader was built.
std::span<const uint32_t> find(std::string_view name);
std::vector<std::string_view> names();
} // namespace pbdsplat::shaders
