#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "core/timer.h"
#include "pbdsplat/args.h"
#include "pbdsplat/commands.h"
#include "pbdsplat/gpu_options.h"
#include "pbdsplat/splat_sphere.h"
#include "render/frame_uniforms.h"
#include "passes/offscreen_renderer.h"
#include "splat/sort.h"

namespace pbdsplat::cli {

int bench_render(const std::vector<std::string>& argv) {
    static constexpr const char* help =
        "usage: pbdsplat bench render [--splats N] [--path gs|mesh|vertex|meshraster] [--sort off|cpu|gpu]\n"
        "                             [--shading fragment|corner] [--environment E] [--width W] [--height H]\n"
        "                             [--footprint gaussian|paper] [--kappa K] [--carrier quad|octagon]\n"
        "                             [--repeat R] [--warmup K] [--json] [--validation] [--device NAME]\n"
        "\n"
        "Milliseconds per frame of the splat pass for N splats on a sphere filling about a third of\n"
        "the image: the GPU time of the sort and draw passes (timestamps), the CPU far-to-near sort\n"
        "when --sort cpu, and the whole frame's wall time; medians of R frames. The three splat\n"
        "paths draw the same image, so their figures compare at equal quality. --path meshraster\n"
        "draws a lit icosphere with about as many vertices as N instead: the mesh pipeline the\n"
        "paper compares against.\n"
        "\n"
        "  --splats N          default 20000\n"
        "  --path P            gs, mesh, vertex (default: the best the device has) or meshraster\n"
        "  --sort S            off (default: the visibility pass), cpu or gpu (compute cull + radix sort)\n"
        "  --shading S         fragment (default) or corner: where the lighting is evaluated\n"
        "  --footprint F       paper (default) or gaussian: the paper's flat disc in one depth-writing\n"
        "                      pass, or the soft Gaussian cut at alpha 1/255 (see docs/BENCHMARKS.md)\n"
        "  --kappa K           Gaussian: cap on the reach in std devs (0, default: none; 3 is the old\n"
        "                      fixed quad); paper: the disc's half-size in s0 (default: closing, 1.8)\n"
        "  --carrier C         quad (default) or octagon (geometry and mesh paths)\n"
        "  --cull-facing C     skip splats whose normal faces the eye by less than the cosine C; the\n"
        "                      sphere is closed and opaque, so by default -0.3, as a scene would (-2: all)\n"
        "  --environment E     position (default), normal, hybrid or off: the shading's lookups\n"
        "  --scale S           splat size multiplier (default 1: sized to close the surface); the\n"
        "                      JSON's coverage says how many screens of quads that draws\n"
        "  --width W, --height H   default 1280x720\n"
        "  --repeat R          measured frames (default 20); --warmup K unmeasured first (default 3)\n"
        "  --json              one JSON object: median_ms (sort + draw), path, and the parts\n";
    std::set<std::string> flags = k_gpu_flags;
    flags.insert({"json", "help"});
    std::set<std::string> valued = k_gpu_options;
    valued.insert({"splats", "path", "sort", "width", "height", "repeat", "warmup", "environment", "shading", "scale",
                   "footprint", "kappa", "carrier", "cull-facing"});
    auto args = Args::parse(argv, flags, valued);
    if (!args.ok()) return usage_error("bench render", args.error().to_string());
    if (args->has("help")) return std::fputs(help, stdout), 0;
    auto count = args->get_uint("splats", 20000, 1, 1u << 24);
    auto width = args->get_uint("width", 1280, 16, 16384);
    auto height = args->get_uint("height", 720, 16, 16384);
    auto repeat = args->get_uint("repeat", 20, 1, 100000);
    auto warmup = args->get_uint("warmup", 3, 0, 100000);
    if (const core::Error* e = first_error(count, width, height, repeat, warmup)) return usage_error("bench render", e->to_string());
    std::optional<render::SplatPath> path;
    const std::string path_arg = args->get_or("path", "auto");
    const bool mesh_raster = path_arg == "meshraster";
    if (path_arg == "gs") path = render::SplatPath::geometry;
    else if (path_arg == "mesh") path = render::SplatPath::mesh;
    else if (path_arg == "vertex") path = render::SplatPath::vertex;
    else if (path_arg != "auto" && !mesh_raster)
        return usage_error("bench render", "--path must be gs, mesh, vertex or meshraster, not '" + path_arg + "'");
    const std::string sort = args->get_or("sort", "off");
    if (sort != "off" && sort != "cpu" && sort != "gpu") return usage_error("bench render", "--sort must be off, cpu or gpu, not '" + sort + "'");
    if (mesh_raster && sort != "off") return usage_error("bench render", "--path meshraster draws opaque triangles: no --sort");
    const std::string shading_arg = args->get_or("shading", "fragment");
    if (shading_arg != "fragment" && shading_arg != "corner")
        return usage_error("bench render", "--shading must be fragment or corner, not '" + shading_arg + "'");

    const std::string footprint_arg = args->get_or("footprint", "paper");
    if (footprint_arg != "gaussian" && footprint_arg != "paper")
        return usage_error("bench render", "--footprint must be gaussian or paper, not '" + footprint_arg + "'");
    const std::string carrier_arg = args->get_or("carrier", "quad");
    if (carrier_arg != "quad" && carrier_arg != "octagon")
        return usage_error("bench render", "--carrier must be quad or octagon, not '" + carrier_arg + "'");
    auto kappa = args->get_float("kappa", 0.0f, 0.0f, 6.0f);
    if (!kappa.ok()) return usage_error("bench render", kappa.error().to_string());
    auto cull_facing = args->get_float("cull-facing", -0.3f, -2.0f, 1.0f);
    if (!cull_facing.ok()) return usage_error("bench render", cull_facing.error().to_string());

    const std::string env_arg = args->get_or("environment", "position");
    render::EnvSampling environment = render::EnvSampling::position;
    if (env_arg == "normal") environment = render::EnvSampling::normal;
    else if (env_arg == "hybrid") environment = render::EnvSampling::hybrid;
    else if (env_arg == "off") environment = render::EnvSampling::off;
    else if (env_arg != "position")
        return usage_error("bench render", "--environment must be position, normal, hybrid or off, not '" + env_arg + "'");

    auto ctx = open_context(args.value());
    if (!ctx.ok()) return fail("bench render", ctx.error().to_string());
    const gpu::DeviceCaps& caps = ctx.value()->caps();
    if (!caps.timestamps) return fail("bench render", "device '" + caps.name + "' has no timestamp queries to measure with");
    if (path) {
        const std::string why = render::splat_path_unsupported(caps, *path);
        if (!why.empty()) return fail("bench render", why);
    }

    auto [records, frame] = make_splat_sphere(count.value());
    frame.lighting.environment.sampling = environment;
    auto scale = args->get_float("scale", 1.0f, 0.01f, 100.0f);
    if (!scale.ok()) return usage_error("bench render", scale.error().to_string());
    frame.style.scale_multiplier = scale.value();
    frame.style.footprint = footprint_arg == "paper" ? render::Footprint::paper : render::Footprint::gaussian;
    frame.style.kappa = kappa.value();
    frame.style.cull_facing = cull_facing.value();
    // Screens of carrier area drawn: each quad spans twice the splat's reach at its distance
    // (about 3.5 here).
    const float sigma = splat::half_to_float(records.front().scale_half);
    const float pixels_per_unit = float(height.value()) / (2.0f * 3.5f * std::tan(math::radians(frame.camera.fov_y_degrees) * 0.5f));
    const float quad_side = 2.0f * render::splat_reach_bound(frame.style) * sigma * pixels_per_unit;
    const double screens = double(quad_side) * quad_side * count.value() / (double(width.value()) * height.value());
    if (mesh_raster) {
        auto r = bench_mesh_raster(*ctx.value(), count.value(), frame, width.value(), height.value(), warmup.value(), repeat.value());
        if (!r.ok()) return fail("bench render", r.error().to_string());
        if (auto v = check_validation(*ctx.value()); !v.ok()) return fail("bench render", v.error().to_string());
        if (args->has("json")) {
            const nlohmann::json j = {{"suite", "render"}, {"device", caps.name}, {"driver", caps.driver},
                                      {"path", "meshraster"}, {"splats", count.value()}, {"vertices", r->vertices},
                                      {"triangles", r->triangles}, {"environment", render::env_sampling_name(environment)},
                                      {"width", width.value()}, {"height", height.value()}, {"repeat", repeat.value()},
                                      {"median_ms", r->median_ms}};
            std::printf("%s\n", j.dump().c_str());
        } else {
            std::printf("device %s (%s)\n", caps.name.c_str(), caps.driver.c_str());
            std::printf("mesh raster of an icosphere (%zu vertices, %zu triangles) at %ux%u, median of %u frames:\n",
                        r->vertices, r->triangles, width.value(), height.value(), repeat.value());
            std::printf("  draw   %8.3f ms GPU\n", r->median_ms);
        }
        return 0;
    }
    if (sort == "cpu") frame.style.order = render::SplatOrder::cpu;
    if (sort == "gpu") frame.style.order = render::SplatOrder::gpu;
    render::RendererOptions options;
    options.gpu_sort = sort == "gpu";
    options.shading = shading_arg == "corner" ? render::SplatShading::corner : render::SplatShading::fragment;
    options.carrier = carrier_arg == "octagon" ? render::SplatCarrier::octagon : render::SplatCarrier::quad;
    options.width = width.value();
    options.height = height.value();
    options.max_splats = count.value();
    options.frames_in_flight = 1;
    options.path = path;
    auto renderer = passes::OffscreenRenderer::create(*ctx.value(), options);
    if (!renderer.ok()) return fail("bench render", renderer.error().to_string());
    const render::SplatPath used = path.value_or(render::best_splat_path(caps));

    splat::SortScratch scratch;
    const Mat4f view = math::look_at(frame.camera.eye, frame.camera.target, frame.camera.up);
    std::vector<double> draw, sort_ms, gpu_sort_ms, wall;
    for (uint32_t i = 0; i < warmup.value() + repeat.value(); ++i) {
        const core::Stopwatch frame_clock;
        double sorting = 0.0;
        if (sort == "cpu") {
            const core::Stopwatch clock;
            splat::sort_far_to_near(records, view, scratch);
            sorting = clock.elapsed_ms();
        }
        if (auto s = renderer.value()->render(records, frame); !s.ok()) return fail("bench render", s.error().to_string());
        auto img = renderer.value()->finish();
        if (!img.ok()) return fail("bench render", img.error().to_string());
        if (i < warmup.value()) continue;
        draw.push_back(renderer.value()->timings().draw_ms);
        gpu_sort_ms.push_back(renderer.value()->timings().sort_ms);
        sort_ms.push_back(sorting);
        wall.push_back(frame_clock.elapsed_ms());
    }
    if (auto v = check_validation(*ctx.value()); !v.ok()) return fail("bench render", v.error().to_string());
    const double median_ms = core::median(draw) + core::median(sort_ms) + core::median(gpu_sort_ms);
    if (args->has("json")) {
        const nlohmann::json j = {{"suite", "render"}, {"device", caps.name}, {"driver", caps.driver},
                                  {"splats", count.value()}, {"path", render::splat_path_name(used)}, {"sort", sort}, {"environment", render::env_sampling_name(environment)}, {"shading", shading_arg},
                                  {"footprint", footprint_arg}, {"kappa", kappa.value()}, {"carrier", carrier_arg},
                                  {"cull_facing", cull_facing.value()},
                                  {"scale", scale.value()}, {"quad_screens", screens},
                                  {"width", width.value()}, {"height", height.value()}, {"repeat", repeat.value()},
                                  {"median_ms", median_ms}, {"draw_ms", core::median(draw)},
                                  {"sort_ms", core::median(sort_ms)}, {"gpu_sort_ms", core::median(gpu_sort_ms)},
                                  {"frame_wall_ms", core::median(wall)}};
        std::printf("%s\n", j.dump().c_str());
        return 0;
    }
    std::printf("device %s (%s)\n", caps.name.c_str(), caps.driver.c_str());
    std::printf("%u splats at %ux%u, path %s, sort %s, shading per %s, median of %u frames:\n", count.value(), width.value(),
                height.value(), render::splat_path_name(used), sort.c_str(), shading_arg.c_str(), repeat.value());
    std::printf("footprint %s, carrier %s, %.1f screens of carrier area\n", footprint_arg.c_str(), carrier_arg.c_str(), screens);
    const bool two_passes = sort == "off" && footprint_arg == "gaussian";
    std::printf("  draw   %8.3f ms GPU (%s)\n", core::median(draw), two_passes ? "visibility + colour passes" : "one pass");
    if (sort == "cpu") std::printf("  sort   %8.3f ms CPU\n", core::median(sort_ms));
    if (sort == "gpu") std::printf("  sort   %8.3f ms GPU (cull, radix sort, gather)\n", core::median(gpu_sort_ms));
    std::printf("  frame  %8.3f ms wall (upload, draw, readback)\n", core::median(wall));
    return 0;
}

} // namespace pbdsplat::cli
