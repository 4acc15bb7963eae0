#include <cstdio>
#include <filesystem>

#include "core/image.h"
#include "pbdsplat/commands.h"
#include "pbdsplat/gpu_options.h"
#include "pbdsplat/upload_path_arg.h"
#include "scene/offscreen_renderer.h"
#include "scene/builtin_scene.h"

namespace pbdsplat::cli {

int cmd_render(const std::vector<std::string>& argv) {
    static constexpr const char* help =
        "usage: pbdsplat render [--out FILE.png] [--width W] [--height H] [--level L]\n"
        "                       [--upload auto|staged|direct] [--validation] [--device NAME]\n"
        "\n"
        "Renders one frame of the built-in scene (an icosphere's vertices as Gaussian splats)\n"
        "offscreen and writes it as a PNG.\n"
        "\n"
        "  --out FILE.png      output image (default out/render.png; the folder is created)\n"
        "  --width W           image width in pixels (default 1280)\n"
        "  --height H          image height in pixels (default 720)\n"
        "  --level L           icosphere subdivision level, 0..7 (default 4: 2,562 splats)\n"
        "  --upload PATH       how records reach the GPU: auto (default), staged, direct\n";
    std::set<std::string> flags = k_gpu_flags;
    flags.insert("help");
    std::set<std::string> valued = k_gpu_options;
    valued.insert({"out", "width", "height", "level", "upload"});
    auto args = Args::parse(argv, flags, valued);
    if (!args.ok()) return usage_error("render", args.error().to_string());
    if (args->has("help")) return std::fputs(help, stdout), 0;
    if (!args->positionals().empty()) return usage_error("render", "takes no positional arguments yet");

    auto width = args->get_uint("width", 1280, 1, 16384);
    auto height = args->get_uint("height", 720, 1, 16384);
    auto level = args->get_uint("level", 4, 0, 7);
    auto upload = parse_upload_path(args->get_or("upload", "auto"));
    for (const core::Error* e : {width.ok() ? nullptr : &width.error(), height.ok() ? nullptr : &height.error(),
                                 level.ok() ? nullptr : &level.error(), upload.ok() ? nullptr : &upload.error()})
        if (e) return usage_error("render", e->to_string());
    const std::filesystem::path out = args->get_or("out", "out/render.png");

    auto ctx = open_context(args.value());
    if (!ctx.ok()) return fail("render", ctx.error().to_string());
    const scene::BuiltinScene scene = scene::make_builtin_scene(level.value());

    render::RendererOptions options;
    options.width = width.value();
    options.height = height.value();
    options.max_splats = uint32_t(scene.records.size());
    options.frames_in_flight = 1;
    options.upload_path = upload.value();
    auto renderer = scene::OffscreenRenderer::create(*ctx.value(), options);
    if (!renderer.ok()) return fail("render", renderer.error().to_string());
    if (auto s = renderer.value()->render(scene.records, scene.frame); !s.ok()) return fail("render", s.error().to_string());
    auto image = renderer.value()->finish();
    if (!image.ok()) return fail("render", image.error().to_string());

    if (out.has_parent_path()) {
        std::error_code ec;
        std::filesystem::create_directories(out.parent_path(), ec);
        if (ec) return fail("render", out.parent_path().string() + ": cannot create the folder: " + ec.message());
    }
    if (auto s = core::write_png(out.string(), image.value()); !s.ok()) return fail("render", s.error().to_string());
    auto v = check_validation(*ctx.value());
    if (!v.ok()) return fail("render", v.error().to_string());
    std::printf("wrote %s (%ux%u, %zu splats, %s uploads, device %s)\n", out.string().c_str(), options.width,
                options.height, scene.records.size(), gpu::upload_path_name(renderer.value()->upload_path()),
                ctx.value()->caps().name.c_str());
    return 0;
}

} // namespace pbdsplat::cli
