#include "pbdsplat/scene_arg.h"

#include "scene/default_scene.h"
#include "scene/scene_file.h"

namespace pbdsplat::cli {

core::Result<scene::Scene> load_scene_arg(const std::vector<std::string>& positionals) {
    if (positionals.size() > 1) return core::make_error("give one scene file (got " + std::to_string(positionals.size()) + ")");
    if (positionals.empty()) return scene::default_scene();
    return scene::load_scene(positionals[0]);
}

} // namespace pbdsplat::cli
