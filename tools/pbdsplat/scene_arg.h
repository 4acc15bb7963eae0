#pragma once
// The scene a command runs: a scene file, a model file of any kind pbdsplat reads (its default
// scene: scene/model_scene.h), or the built-in default when none is named. Told apart by content.
#include <string>
#include <vector>

#include "core/result.h"
#include "pbdsplat/options.h"
#include "scene/scene.h"

namespace pbdsplat::cli {

// --save-scene FILE.toml: the scene used, written where the user can edit it.
Option save_scene_option();

core::Result<scene::Scene> load_scene_arg(const std::vector<std::string>& positionals);
// The same, then --save-scene when given; `positionals` when the command's operands hold more
// than the scene (export-ply's output).
core::Result<scene::Scene> load_scene_arg(const Options& options);
core::Result<scene::Scene> load_scene_arg(const Options& options, const std::vector<std::string>& positionals);

} // namespace pbdsplat::cli
