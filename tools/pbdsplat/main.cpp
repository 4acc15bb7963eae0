// pbdsplat: soft bodies simulated with position-based dynamics, cut and torn, and rendered as
// Gaussian splats. One program, one command per job.
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "core/spelling.h"
#include "pbdsplat/commands.h"
#include "pbdsplat/progress.h"

namespace {

constexpr const char* k_help =
    "usage: pbdsplat <command> [options]\n"
    "\n"
    "commands:\n"
    "  info      the Vulkan device and the features that matter (--json)\n"
    "  run       run a scene live in a window: drag, cut, tear (needs a display)\n"
    "  render    run a scene offscreen (default: the built-in one) and write PNG images\n"
    "  graph     the compiled frame graph of a scene, with culled passes marked (--json, --dot)\n"
    "  validate-scene  check scene files without running them\n"
    "  check     run a scene and measure shape, strays, holes, pieces and volume (--json)\n"
    "  export-ply  a scene's Gaussians at a frame, as a 3DGS .ply\n"
    "  bench     benchmarks that print figures (bench --help lists them)\n"
    "\n"
    "Every command takes --help. Errors go to stderr with a non-zero exit. Long commands\n"
    "(render, export-ply, bench scene, surface, splat) print progress to stderr; --quiet, given\n"
    "to any command, silences it.\n";

struct Command {
    const char* name;
    int (*run)(const std::vector<std::string>&);
};
constexpr Command k_commands[] = {
    {"info", pbdsplat::cli::cmd_info},
    {"run", pbdsplat::cli::cmd_run},
    {"render", pbdsplat::cli::cmd_render},
    {"bench", pbdsplat::cli::cmd_bench},
    {"graph", pbdsplat::cli::cmd_graph},
    {"validate-scene", pbdsplat::cli::cmd_validate_scene},
    {"check", pbdsplat::cli::cmd_check},
    {"export-ply", pbdsplat::cli::cmd_export_ply},
};

} // namespace

namespace pbdsplat::cli {
int fail(const std::string& command, const std::string& message) {
    std::fprintf(stderr, "pbdsplat %s: %s\n", command.c_str(), message.c_str());
    return 1;
}
int usage_error(const std::string& command, const std::string& message) {
    std::fprintf(stderr, "pbdsplat %s: %s\n", command.c_str(), message.c_str());
    return 2;
}
} // namespace pbdsplat::cli

int main(int argc, char** argv) {
    if (argc < 2 || std::strcmp(argv[1], "--help") == 0 || std::strcmp(argv[1], "-h") == 0 ||
        std::strcmp(argv[1], "help") == 0) {
        std::fputs(k_help, argc < 2 ? stderr : stdout);
        return argc < 2 ? 2 : 0;
    }
    // --quiet belongs to every command (the progress lines are shared), so it is taken here.
    std::vector<std::string> args;
    for (int i = 2; i < argc; ++i) {
        if (std::strcmp(argv[i], "--quiet") == 0) pbdsplat::cli::Progress::set_quiet(true);
        else args.emplace_back(argv[i]);
    }
    for (const Command& c : k_commands)
        if (std::strcmp(argv[1], c.name) == 0) return c.run(args);
    std::vector<std::string> names;
    for (const Command& c : k_commands) names.emplace_back(c.name);
    const auto near = pbdsplat::core::nearest_spelling(argv[1], names);
    std::fprintf(stderr, "pbdsplat: unknown command '%s'%s (see pbdsplat --help)\n", argv[1],
                 near ? ("; did you mean '" + *near + "'?").c_str() : "");
    return 2;
}
