#include <cstdio>

#include "pbdsplat/options.h"
#include "pbdsplat/commands.h"
#include "scene/model_scene.h"
#include "scene/scene_file.h"
#include "scene/scene_runtime.h"

namespace pbdsplat::cli {

int cmd_validate_scene(const std::vector<std::string>& argv) {
    static const CommandSpec command{
        "validate-scene", "FILE.toml|MODEL...",
        "Checks scene files without running them: every key known, of the right type and in range\n"
        "(docs/scene-format.md), and the model found and usable. A model file (told apart by content)\n"
        "is checked as its default scene: read, closed and sampled as run would. Prints one line per\n"
        "file; the first error of a file names its line and column. Exits 1 if any file is invalid.\n",
        {}};
    const Parsed parsed = parse_command(command, argv);
    if (!parsed.options) return parsed.exit_code;
    if (parsed.options->operands().empty()) return usage_error("validate-scene", "name at least one scene file");
    int bad = 0;
    for (const std::string& file : parsed.options->operands()) {
        auto s = scene::load_scene_or_model(file);
        if (s.ok()) {
            auto body = scene::make_scene_body(s.value());  // the model must load and be usable
            if (!body.ok()) {
                std::fprintf(stderr, "%s: %s\n", file.c_str(), body.error().to_string().c_str());
                ++bad;
                continue;
            }
            std::printf("ok: %s (%zu particles, %zu events)\n", file.c_str(), body->particle_count(), s->events.size());
        } else {
            std::fprintf(stderr, "%s\n", s.error().to_string().c_str());
            ++bad;
        }
    }
    return bad ? 1 : 0;
}

} // namespace pbdsplat::cli
