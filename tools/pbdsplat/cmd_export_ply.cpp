#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "pbdsplat/options.h"
#include "pbdsplat/commands.h"
#include "pbdsplat/progress.h"
#include "pbdsplat/scene_arg.h"
#include "scene/scene_runtime.h"
#include "render/environment.h"
#include "scene/ply_view.h"
#include "splat/ply.h"

namespace pbdsplat::cli {

int cmd_export_ply(const std::vector<std::string>& argv) {
    static const CommandSpec command{
        "export-ply", "[SCENE.toml | MODEL] OUT.ply",
        "Simulates a scene (default: the built-in one) for N frames and writes its Gaussians (the\n"
        "particles and the boundary particles) as the binary PLY that Gaussian-splat viewers read:\n"
        "x y z, nx ny nz, f_dc_0..2, [f_rest_*,] opacity (logit), scale_0..2 (log), rot_0..3.\n"
        "The colour is the base colour (no lighting baked in); the opacity includes a splat's fade-in\n"
        "after a cut. A deformed-shape scene writes its splats' rotations and scales.\n"
        "`pbdsplat render OUT.ply` renders such a file as a static scene.\n",
        {whole("frame", "N", 1, 1, 10000000, "frames to simulate first"),
         text("frames", "A:B", "", "a sequence: frames A to B (1-based, both included), one file each,\n"
                                   "OUT_0000A.ply ... (OUT.ply's stem, the frame number in five digits)")
             .default_from("none"),
         choice("up", {"-y", "y"}, "-y",
                "which way is up in the file: -y is 3D Gaussian splatting's convention (captures are\n"
                "y-down), so other viewers and converters show the body upright; y keeps pbdsplat's\n"
                "y-up world as it is. The two differ by a half turn about x, not a mirror"),
         flag("bake-shading", "write each splat's lit colour as this scene shades it from its camera\n"
                              "(key light, environment, lights) instead of the base colour: viewers\n"
                              "without the paper's lighting then show what pbdsplat shows"),
         choice("sh-degree", {"0", "3"}, "0",
                "0: no f_rest columns (pbdsplat has no view-dependent colour, so they would be zeros,\n"
                "4.4x the file); 3: the 45 zero columns, for tools that insist on them"),
         save_scene_option()}};
    const Parsed parsed = parse_command(command, argv);
    if (!parsed.options) return parsed.exit_code;
    const Options& opt = *parsed.options;
    uint32_t first = opt.whole("frame"), last = first;
    if (opt.given("frames")) {
        if (opt.given("frame")) return usage_error("export-ply", "give --frame N or --frames A:B, not both");
        const std::string& range = opt.text("frames");
        unsigned a = 0, b = 0;
        char colon = 0, extra = 0;
        if (std::sscanf(range.c_str(), "%u%c%u%c", &a, &colon, &b, &extra) != 3 || colon != ':' || a < 1 || b < a || b > 10000000)
            return usage_error("export-ply", "--frames takes A:B with 1 <= A <= B, not '" + range + "'");
        first = a, last = b;
    }
    splat::PlyWriteOptions write;
    write.up = opt.text("up") == "y" ? splat::PlyUp::y : splat::PlyUp::minus_y;
    write.sh_degree = opt.text("sh-degree") == "3" ? 3 : 0;
    std::vector<std::string> positionals = opt.operands();
    if (positionals.empty() || positionals.back().size() < 4 ||
        positionals.back().compare(positionals.back().size() - 4, 4, ".ply") != 0)
        return usage_error("export-ply", "name the output file, ending in .ply");
    const std::string out = positionals.back();
    positionals.pop_back();
    // Made up front, as render does: the README's `out/f60.ply` works in a fresh checkout, and
    // a folder that cannot be made fails before the simulation runs.
    if (const std::filesystem::path dir = std::filesystem::path(out).parent_path(); !dir.empty()) {
        std::error_code ec;
        std::filesystem::create_directories(dir, ec);
        if (ec) return fail("export-ply", dir.string() + ": cannot create the folder: " + ec.message());
    }
    auto scene = load_scene_arg(opt, positionals);
    if (!scene.ok()) return fail("export-ply", scene.error().to_string());
    scene::RuntimeOptions options;
    options.keep_records = true;
    auto runtime = scene::SceneRuntime::create(scene.value(), options);
    if (!runtime.ok()) return fail("export-ply", runtime.error().to_string());
    const bool sequence = opt.given("frames");
    std::optional<render::EnvironmentMap> map;
    if (opt.flag("bake-shading")) {
        auto m = render::make_environment_map(scene->render.environment_map, scene->render.frame.lighting.direction);
        if (!m.ok()) return fail("export-ply", m.error().to_string());
        map = std::move(m).value();
    }
    std::vector<splat::GaussianRecord> baked;
    Progress progress("export-ply", last);
    for (uint32_t f = 1; f <= last; ++f) {
        if (auto s = runtime.value()->step(); !s.ok()) return fail("export-ply", s.error().to_string());
        if (last > 1) progress.frame_done(f);
        if (f < first) continue;
        std::string file = out;
        if (sequence) {
            char number[16];
            std::snprintf(number, sizeof(number), "_%05u", f);
            file = out.substr(0, out.size() - 4) + number + ".ply";
        }
        std::span<const splat::GaussianRecord> records = runtime.value()->records();
        if (map) {
            baked.assign(records.begin(), records.end());
            scene::bake_shading(runtime.value()->frame_inputs(), *map, baked);
            records = baked;
        }
        if (auto s = splat::write_ply(file, records, runtime.value()->shapes(), write); !s.ok())
            return fail("export-ply", s.error().to_string());
        if (!sequence) {
            // A scene may draw its boundary particles alone (a coarse simulation under a fine
            // surface): the particles drawn are what the records hold beyond those and the cut
            // faces' samples.
            const scene::FrameStats& st = runtime.value()->stats();
            const size_t beyond_boundary = st.gaussians - std::min(st.gaussians, st.boundary_particles);
            const size_t faces = std::min(runtime.value()->cut_faces().samples(), beyond_boundary);
            const size_t drawn_particles = beyond_boundary - faces;
            std::printf("wrote %s (%zu Gaussians: %zu boundary particles + %zu of the %zu simulation particles + %zu on cut faces, frame %u, %s up)\n",
                        file.c_str(), st.gaussians, st.boundary_particles, drawn_particles, st.particles, faces, f,
                        opt.text("up") == "y" ? "+y" : "-y");
        }
    }
    if (sequence)
        std::printf("wrote %u files, frames %u to %u, %s_%05u.ply ... (%s up)\n", last - first + 1, first, last,
                    out.substr(0, out.size() - 4).c_str(), first, opt.text("up") == "y" ? "+y" : "-y");
    return 0;
}

} // namespace pbdsplat::cli
