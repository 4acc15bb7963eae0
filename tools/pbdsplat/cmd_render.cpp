#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/image.h"
#include "core/timer.h"
#include "pbdsplat/commands.h"
#include "pbdsplat/gpu_options.h"
#include "pbdsplat/progress.h"
#include "pbdsplat/scene_arg.h"
#include "pbdsplat/upload_path_arg.h"
#include "pbdsplat/options.h"
#include "passes/offscreen_renderer.h"
#include "scene/scene_runtime.h"
#include "splat/ply.h"
#include "scene/model_scene.h"
#include "scene/ply_view.h"

namespace pbdsplat::cli {
namespace {

bool ffmpeg_available() { return std::system("command -v ffmpeg >/dev/null 2>&1") == 0; }

// "x,y,z" as given on the command line.
core::Result<Vec3f> parse_vec3(const std::string& text) {
    Vec3f v;
    char sep1 = 0, sep2 = 0;
    std::istringstream in(text);
    if (!(in >> v.x() >> sep1 >> v.y() >> sep2 >> v.z()) || sep1 != ',' || sep2 != ',' || !v.allFinite())
        return core::make_error("expected three finite numbers like 0,1,3, not '" + text + "'");
    std::string rest;
    if (in >> rest) return core::make_error("expected three finite numbers like 0,1,3, not '" + text + "'");
    return v;
}

// A .ply of Gaussians as a static scene, drawn as it was trained (scene/ply_view.h).
int render_ply(const std::string& file, const Options& opt, uint32_t width, uint32_t height, const std::filesystem::path& out) {
    const bool lit = opt.flag("lit");
    core::Stopwatch clock;
    auto gaussians = splat::read_ply_gaussians(file, opt.text("up") == "y" ? splat::PlyUp::y : splat::PlyUp::minus_y,
                                               lit ? splat::MissingNormals::estimate : splat::MissingNormals::leave);
    if (!gaussians.ok()) return fail("render", gaussians.error().to_string());
    if (gaussians->dropped_nonfinite)
        std::fprintf(stderr, "pbdsplat render: warning: %s: %zu Gaussians with NaN or infinite values left out\n", file.c_str(),
                     gaussians->dropped_nonfinite);
    if (const splat::NormalEstimate& e = gaussians->estimated; gaussians->normals_estimated)
        std::fprintf(stderr,
                     "pbdsplat render: note: %s: %zu Gaussians without a normal: %zu took their flattest axis, %zu the plane of "
                     "their neighbours, %zu face +z in the file (too few neighbours, or none in a plane)\n",
                     file.c_str(), gaussians->missing_normals, e.from_shape, e.from_neighbours, e.unresolved);
    if (gaussians->records.empty()) return fail("render", file + ": holds no Gaussians");
    const double load_ms = clock.elapsed_ms();
    render::FrameInputs frame = scene::ply_view(gaussians->records, lit);
    // The automatic camera, unless told otherwise.
    for (const char* key : {"eye", "target"}) {
        if (!opt.given(key)) continue;
        auto v = parse_vec3(opt.text(key));
        if (!v.ok()) return usage_error("render", std::string("--") + key + ": " + v.error().message);
        (std::string(key) == "eye" ? frame.camera.eye : frame.camera.target) = v.value();
    }
    if ((frame.camera.eye - frame.camera.target).norm() < 1e-6f) return usage_error("render", "--eye and --target coincide");
    if (opt.given("fov")) frame.camera.fov_y_degrees = opt.real("fov");
    auto ctx = open_context(opt);
    if (!ctx.ok()) return fail("render", ctx.error().to_string());
    const bool gpu_sort = opt.given("sort") ? opt.text("sort") == "gpu" : scene::ply_sort_on_gpu(ctx.value()->caps().type);
    scene::order_ply(gaussians.value(), frame, gpu_sort);
    const render::RendererOptions ro =
        scene::ply_renderer_options(gaussians.value(), width ? width : 1280, height ? height : 720, gpu_sort);
    auto renderer = passes::OffscreenRenderer::create(*ctx.value(), ro);
    if (!renderer.ok()) return fail("render", renderer.error().to_string());
    if (auto s = renderer.value()->render(gaussians->records, frame, {}, gaussians->shapes, gaussians->sh); !s.ok())
        return fail("render", s.error().to_string());
    auto image = renderer.value()->finish();
    if (!image.ok()) return fail("render", image.error().to_string());
    const std::filesystem::path target = out.extension() == ".png" ? out : out / "frame_0000.png";
    if (auto s = core::write_png(target.string(), image.value()); !s.ok()) return fail("render", s.error().to_string());
    if (auto v = check_validation(*ctx.value()); !v.ok()) return fail("render", v.error().to_string());
    std::printf("wrote %s (%zu %s Gaussians%s from %s; read in %.2f s, written %.2f s after the command began)\n",
                target.string().c_str(), gaussians->records.size(), gaussians->shapes.empty() ? "round" : "anisotropic",
                gaussians->sh.empty() ? "" : (", colour of degree " + std::to_string(gaussians->sh_degree)).c_str(), file.c_str(),
                load_ms / 1000.0, clock.elapsed_ms() / 1000.0);
    return 0;
}

} // namespace

int cmd_render(const std::vector<std::string>& argv) {
    static const CommandSpec command{
        "render", "[SCENE.toml | MODEL | GAUSSIANS.ply]",
        "Runs a scene (default: the built-in scenes/default.toml) offscreen for N frames and writes\n"
        "images. With --out ending in .png, the last frame goes to that file; otherwise PATH is a\n"
        "folder that receives frame_0000.png, frame_0001.png, ..., frames.csv (particle counts,\n"
        "boundary particles inserted, retired and fading by the density control, and\n"
        "per-stage milliseconds and uploaded bytes of every frame) and, when ffmpeg is on the PATH, video.mp4.\n"
        "A .ply of Gaussians (3DGS layout, e.g. from export-ply or a trained capture) renders as one\n"
        "static image, as it was trained: soft Gaussians far to near, unlit, with its rotations, scales\n"
        "and view-dependent colour; the camera frames it unless --eye/--target/--fov say otherwise.\n"
        "Progress goes to stderr: a bar on a terminal, a line every 2 s otherwise (--quiet: none).\n",
        with_gpu({whole("frames", "N", 1, 1, 1000000, "frames to simulate and render"),
                  text("out", "PATH", "out/render.png", "output file (.png) or folder"),
                  whole("width", "W", 0, 16, 16384, "image width").default_from("the scene's; 1280 for a .ply"),
                  whole("height", "H", 0, 16, 16384, "image height").default_from("the scene's; 720 for a .ply"),
                  whole("threads", "T", 1, 1, 64, "simulation threads"), upload_option(),
                  choice("up", {"-y", "y"}, "-y", ".ply only: which way is up in the file (-y: 3DGS's convention)"),
                  text("eye", "X,Y,Z", "", ".ply only: the camera's eye").default_from("framing the file"),
                  text("target", "X,Y,Z", "", ".ply only: the point looked at").default_from("the file's centre"),
                  real("fov", "DEGREES", 0.0f, 1.0f, 170.0f, ".ply only: vertical field of view").default_from("framing the file"),
                  flag("lit", ".ply only: shade with a scene's default lights and environment, by the file's\n"
                              "normals (estimated where it has none), instead of as stored"),
                  choice("sort", {"cpu", "gpu"}, "cpu", ".ply only: where the Gaussians are ordered far to near")
                      .default_from("gpu on a GPU, cpu on a CPU device"),
                  save_scene_option()})};
    const Parsed parsed = parse_command(command, argv);
    if (!parsed.options) return parsed.exit_code;
    const Options& opt = *parsed.options;
    const uint32_t frames = opt.whole("frames"), width = opt.whole("width"), height = opt.whole("height");
    const uint32_t threads = opt.whole("threads");
    const std::filesystem::path out = opt.text("out");
    const std::string out_ext = out.extension().string();
    for (const char* image : {".jpg", ".jpeg", ".bmp", ".tga", ".gif", ".webp", ".exr", ".tif", ".tiff", ".hdr", ".ppm"})
        if (out_ext == image)
            return usage_error("render", "--out " + out.string() + ": only PNG images are written; end it in .png, or name a folder");
    const bool single = out_ext == ".png";
    const std::filesystem::path dir = single ? out.parent_path() : out;
    if (!dir.empty()) {
        std::error_code ec;
        std::filesystem::create_directories(dir, ec);
        if (ec) return fail("render", dir.string() + ": cannot create the folder: " + ec.message());
    }
    const auto& pos = opt.operands();
    if (pos.size() == 1) {
        // Told apart by content: a mesh .ply is a model, a 3DGS .ply Gaussians.
        auto kind = scene::input_kind(pos[0]);
        if (!kind.ok()) return fail("render", kind.error().to_string());
        if (kind.value() == scene::InputKind::gaussians) {
            if (opt.given("save-scene")) return usage_error("render", "--save-scene applies to a scene or a model, not to Gaussians");
            return render_ply(pos[0], opt, width, height, out);
        }
    }
    for (const char* key : {"up", "eye", "target", "fov", "lit", "sort"})
        if (opt.given(key)) return usage_error("render", std::string("--") + key + " applies to a .ply; a scene sets its own camera and lighting");

    auto scene = load_scene_arg(opt);
    if (!scene.ok()) return fail("render", scene.error().to_string());
    if (width) scene->render.width = width;
    if (height) scene->render.height = height;

    auto ctx = open_context(opt);
    if (!ctx.ok()) return fail("render", ctx.error().to_string());
    scene::RuntimeOptions options;
    options.gpu = ctx.value().get();
    options.threads = threads;
    options.upload_path = upload_path(opt);
    options.frames_in_flight = 1;  // every frame's image is read back and written
    auto runtime = scene::SceneRuntime::create(scene.value(), options);
    if (!runtime.ok()) return fail("render", runtime.error().to_string());

    std::ofstream csv;
    if (!single) {
        csv.open(dir / "frames.csv");
        if (!csv) return fail("render", (dir / "frames.csv").string() + ": cannot write");
        csv << "frame,time,particles,gaussians,";
        for (const auto& n : scene::k_pass_groups) csv << n.csv << ',';
        csv << "frame_ms,uploaded_bytes,samples_inserted,samples_retired,samples_fading\n";
    }
    Progress progress("render", frames);
    for (uint32_t f = 0; f < frames; ++f) {
        if (auto s = runtime.value()->step(); !s.ok()) return fail("render", s.error().to_string());
        if (!single || f + 1 == frames) {
            auto image = runtime.value()->finish();
            if (!image.ok()) return fail("render", image.error().to_string());
            char name[32];
            std::snprintf(name, sizeof(name), "frame_%04u.png", f);
            const std::filesystem::path file = single ? out : dir / name;
            if (auto s = core::write_png(file.string(), image.value(), true); !s.ok()) return fail("render", s.error().to_string());
        }
        if (csv) {
            const auto& s = runtime.value()->stats();
            csv << s.frame - 1 << ',' << s.time << ',' << s.particles << ',' << s.gaussians << ',';
            for (double ms : s.groups.ms) csv << ms << ',';
            csv << s.graph_ms << ',' << s.uploaded_bytes << ','
                << s.density.inserted << ',' << s.density.retired << ',' << s.density.fading << '\n';
        }
        if (frames > 1) progress.frame_done(f + 1);
    }
    if (auto v = check_validation(*ctx.value()); !v.ok()) return fail("render", v.error().to_string());
    if (single) {
        std::printf("wrote %s (%ux%u, scene %s, %zu splats, frame %u)\n", out.string().c_str(), scene->render.width,
                    scene->render.height, scene->name.c_str(), runtime.value()->stats().gaussians, frames);
        return 0;
    }
    std::printf("wrote %u frames and frames.csv to %s\n", frames, dir.string().c_str());
    if (ffmpeg_available()) {
        const std::string cmd = "ffmpeg -loglevel error -y -framerate " +
                                std::to_string(int(std::lround(1.0 / scene->simulation.dt))) + " -i '" +
                                (dir / "frame_%04d.png").string() + "' -pix_fmt yuv420p '" + (dir / "video.mp4").string() + "'";
        if (std::system(cmd.c_str()) == 0) std::printf("wrote %s\n", (dir / "video.mp4").string().c_str());
        else std::fprintf(stderr, "pbdsplat render: ffmpeg failed; the PNG sequence is complete\n");
    } else {
        std::fprintf(stderr, "pbdsplat render: no video.mp4: ffmpeg is not on the PATH (apt-get install ffmpeg)\n");
    }
    return 0;
}

} // namespace pbdsplat::cli
