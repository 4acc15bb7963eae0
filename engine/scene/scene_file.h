#pragma once
// Scene files in TOML (docs/scene-format.md). Unknown keys, wrong types and values out of range
// are errors with the file, line and column.
#include <string>

#include "core/result.h"
#include "scene/scene.h"

namespace pbdsplat::scene {

core::Result<Scene> load_scene(const std::string& path);
// `name` stands for the file in error messages.
core::Result<Scene> parse_scene(const std::string& text, const std::string& name);
// The scene as TOML that parse_scene reads back to the same scene.
std::string to_toml(const Scene& scene);

} // namespace pbdsplat::scene
