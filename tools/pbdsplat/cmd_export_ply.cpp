#include <cstdio>

#include "pbdsplat/args.h"
#include "pbdsplat/commands.h"
#include "pbdsplat/scene_arg.h"
#include "scene/scene_runtime.h"
#include "splat/ply.h"

namespace pbdsplat::cli {

int cmd_export_ply(const std::vector<std::string>& argv) {
    static constexpr const char* help =
        "usage: pbdsplat export-ply [SCENE.toml] [--frame N] OUT.ply\n"
        "\n"
        "Simulates a scene (default: the built-in one) for N frames and writes its Gaussians (the\n"
        "particles and the boundary particles) as the binary PLY that Gaussian-splat viewers read:\n"
        "x y z, nx ny nz, f_dc_0..2, f_rest_0..44, opacity (logit), scale_0..2 (log), rot_0..3.\n"
        "`pbdsplat render OUT.ply` renders such a file as a static scene.\n"
        "\n"
        "  --frame N           frames to simulate first (default 1)\n";
    auto args = Args::parse(argv, {"help"}, {"frame"});
    if (!args.ok()) return usage_error("export-ply", args.error().to_string());
    if (args->has("help")) return std::fputs(help, stdout), 0;
    auto frame = args->get_uint("frame", 1, 1, 10000000);
    if (!frame.ok()) return usage_error("export-ply", frame.error().to_string());
    std::vector<std::string> positionals = args->positionals();
    if (positionals.empty() || positionals.back().size() < 4 ||
        positionals.back().compare(positionals.back().size() - 4, 4, ".ply") != 0)
        return usage_error("export-ply", "name the output file, ending in .ply");
    const std::string out = positionals.back();
    positionals.pop_back();
    auto scene = load_scene_arg(positionals);
    if (!scene.ok()) return fail("export-ply", scene.error().to_string());
    scene::RuntimeOptions options;
    options.keep_records = true;
    auto runtime = scene::SceneRuntime::create(scene.value(), options);
    if (!runtime.ok()) return fail("export-ply", runtime.error().to_string());
    for (uint32_t f = 0; f < frame.value(); ++f)
        if (auto s = runtime.value()->step(); !s.ok()) return fail("export-ply", s.error().to_string());
    if (auto s = splat::write_ply(out, runtime.value()->records()); !s.ok()) return fail("export-ply", s.error().to_string());
    std::printf("wrote %s (%zu Gaussians: %zu particles + %zu boundary particles, frame %u)\n", out.c_str(),
                runtime.value()->records().size(), runtime.value()->stats().particles,
                runtime.value()->stats().boundary_particles, frame.value());
    return 0;
}

} // namespace pbdsplat::cli
