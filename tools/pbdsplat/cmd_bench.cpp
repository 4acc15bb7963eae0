#include <cstdio>

#include "pbdsplat/bench_suites.h"

#include "core/spelling.h"
#include "pbdsplat/commands.h"

namespace pbdsplat::cli {
namespace {

// In the order `pbdsplat bench --help` lists them.
const BenchSuite* const k_suites[] = {&k_bench_sim,    &k_bench_sim_error, &k_bench_graph,        &k_bench_scene,
                                      &k_bench_surface, &k_bench_cut,       &k_bench_render,       &k_bench_render_error,
                                      &k_bench_temporal, &k_bench_coverage, &k_bench_splat, &k_bench_load};

std::string bench_help() {
    std::string help = "usage: pbdsplat bench <suite> [options]\n\nsuites:\n";
    for (const BenchSuite* s : k_suites) {
        std::string name = s->name;
        help += "  " + name + std::string(name.size() < 13 ? 13 - name.size() : 1, ' ') + s->summary + "\n";
    }
    return help + "\n`pbdsplat bench SCENE.toml [options]` runs the scene suite on that file.\n"
                  "Every suite takes --help and --json; those that write files take --out-dir.\n";
}

} // namespace

int cmd_bench(const std::vector<std::string>& argv) {
    if (argv.empty() || argv[0] == "--help" || argv[0] == "-h") {
        std::fputs(bench_help().c_str(), argv.empty() ? stderr : stdout);
        return argv.empty() ? 2 : 0;
    }
    // `pbdsplat bench FILE.toml` is `pbdsplat bench scene FILE.toml`.
    if (argv[0].size() > 5 && argv[0].compare(argv[0].size() - 5, 5, ".toml") == 0) return run_bench(k_bench_scene, argv);
    const std::vector<std::string> rest(argv.begin() + 1, argv.end());
    for (const BenchSuite* s : k_suites)
        if (argv[0] == s->name) return run_bench(*s, rest);
    std::vector<std::string> names;
    for (const BenchSuite* s : k_suites) names.emplace_back(s->name);
    const auto near = core::nearest_spelling(argv[0], names);
    return usage_error("bench", "unknown suite '" + argv[0] + "'" + (near ? "; did you mean '" + *near + "'?" : std::string()) +
                                    " (see pbdsplat bench --help)");
}

} // namespace pbdsplat::cli
