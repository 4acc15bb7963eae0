#include <cstdio>

#include "pbdsplat/commands.h"

namespace pbdsplat::cli {
namespace {

constexpr const char* k_bench_help =
    "usage: pbdsplat bench <suite> [options]\n"
    "\n"
    "suites:\n"
    "  sim       Stage A milliseconds per frame, per stage (median of frames)\n"
    "  sim-error Stage A run time against error, PBD and XPBD, to CSV and SVG plots\n"
    "  graph     the frame graph's own overhead per frame\n"
    "  scene     a scene through its frame graph: median ms per stage and per frame\n"
    "  surface   boundary particles: sampling and update time, coverage against eta\n"
    "  cut       one line cut: its milliseconds, the crossed region, Stage A before and after\n"
    "  render    splat pass ms per frame by path (gs, mesh, vertex, meshraster), sort, shading\n"
    "  render-error  rendering time against image error, against a supersampled reference\n"
    "  temporal  frame-to-frame luminance change (flicker) of splats and mesh, around a cut\n"
    "  coverage  hole ratio and silhouette IoU through deformation and cuts, by surface mode\n"
    "  splat     GPU milliseconds of upload, draw and readback for N splats (median of repeats)\n"
    "\n"
    "`pbdsplat bench SCENE.toml [options]` runs the scene suite on that file.\n"
    "Every suite takes --help and --json.\n";

} // namespace

int cmd_bench(const std::vector<std::string>& argv) {
    if (argv.empty() || argv[0] == "--help" || argv[0] == "-h") {
        std::fputs(k_bench_help, argv.empty() ? stderr : stdout);
        return argv.empty() ? 2 : 0;
    }
    const std::vector<std::string> rest(argv.begin() + 1, argv.end());
    if (argv[0] == "splat") return bench_splat(rest);
    if (argv[0] == "sim") return bench_sim(rest);
    if (argv[0] == "sim-error") return bench_sim_error(rest);
    if (argv[0] == "scene") return bench_scene(rest);
    // `pbdsplat bench FILE.toml` is `pbdsplat bench scene FILE.toml`.
    if (argv[0].size() > 5 && argv[0].compare(argv[0].size() - 5, 5, ".toml") == 0) return bench_scene(argv);
    if (argv[0] == "graph") return bench_graph(rest);
    if (argv[0] == "surface") return bench_surface(rest);
    if (argv[0] == "cut") return bench_cut(rest);
    if (argv[0] == "render") return bench_render(rest);
    if (argv[0] == "render-error") return bench_render_error(rest);
    if (argv[0] == "temporal") return bench_temporal(rest);
    if (argv[0] == "coverage") return bench_coverage(rest);
    return usage_error("bench", "unknown suite '" + argv[0] + "' (see pbdsplat bench --help)");
}

} // namespace pbdsplat::cli
