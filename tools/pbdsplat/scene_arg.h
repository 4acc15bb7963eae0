#pragma once
// The scene a command runs: the file named on the command line, or the built-in default.
#include <string>
#include <vector>

#include "core/result.h"
#include "scene/scene.h"

namespace pbdsplat::cli {

core::Result<scene::Scene> load_scene_arg(const std::vector<std::string>& positionals);

} // namespace pbdsplat::cli
