#include <cmath>

#include "core/names.h"
#include "core/timer.h"
#include "pbdsplat/bench_suites.h"
#include "pbdsplat/gpu_options.h"
#include "pbdsplat/splat_sphere.h"
#include "render/frame_uniforms.h"
#include "passes/offscreen_renderer.h"
#include "scene/ply_view.h"
#include "splat/ply.h"
#include "splat/sort.h"

namespace pbdsplat::cli {

namespace {

const CommandSpec& command_spec() {
    static const CommandSpec command{
        "bench render", "",
        "Milliseconds per frame of the splat pass for N splats on a sphere filling about a third of\n"
        "the image: the GPU time of the sort and draw passes (timestamps), the CPU far-to-near sort\n"
        "when --sort cpu, and the whole frame's wall time; medians of R frames. The three splat\n"
        "paths draw the same image, so their figures compare at equal quality. --path meshraster\n"
        "draws a lit icosphere with about as many vertices as N instead: the mesh pipeline the\n"
        "paper compares against. --ply FILE measures a capture instead (a 3DGS .ply): an orbit of\n"
        "R frames about it as `render FILE.ply` draws it (anisotropic, view-dependent colour, unlit,\n"
        "far to near), with the file's read time and, per frame, the sort and the GPU draw (--sort\n"
        "cpu or gpu; by default the GPU's own on a GPU, the CPU's on a CPU device such as Lavapipe).\n",
        with_gpu({whole("splats", "N", 20000, 1, 1u << 24, "splats on the sphere"),
                  text("ply", "FILE", "", "a capture (3DGS .ply) to orbit instead of the sphere").default_from("none"),
                  choice("path", {"auto", "gs", "mesh", "vertex", "meshraster"}, "auto",
                         "the splat path (auto: the best the device has), or the lit mesh"),
                  choice("sort", {"off", "cpu", "gpu"}, "off",
                         "off: the visibility pass; cpu; gpu: compute cull and radix sort"),
                  choice("shading", {"fragment", "corner"}, "fragment", "where the lighting is evaluated"),
                  choice("footprint", {"paper", "gaussian"}, "paper",
                         "the paper's flat disc in one depth-writing pass, or the soft Gaussian cut at\n"
                         "alpha 1/255 (see docs/BENCHMARKS.md)"),
                  choice("blend", {"over", "normalised"}, "over",
                         "over: composited (with the visibility pass when unsorted); normalised: the\n"
                         "front splats averaged, then resolved (needs --footprint gaussian, no --sort)"),
                  real("kappa", "K", 0.0f, 0.0f, 6.0f,
                       "Gaussian: cap on the reach in std devs (0: none, the 1/255 cut-off alone);\n"
                       "paper: the disc's half-size in s0 (0: closing, 1.8)"),
                  choice("carrier", {"quad", "octagon"}, "quad", "the primitive around each splat (geometry and mesh paths)"),
                  real("cull-facing", "C", -0.3f, -2.0f, 1.0f,
                       "skip splats whose normal faces the eye by less than the cosine C; the sphere is\n"
                       "closed and opaque, so -0.3 as a scene would (-2: all)"),
                  choice("environment", {"position", "normal", "hybrid", "off"}, "position", "the shading's lookups"),
                  real("scale", "S", 1.0f, 0.01f, 100.0f,
                       "splat size multiplier (1: sized to close the surface); the JSON's coverage\n"
                       "says how many screens of quads that draws"),
                  whole("width", "W", 1280, 16, 16384, "image width"), whole("height", "H", 720, 16, 16384, "image height"),
                  whole("repeat", "R", 20, 1, 100000, "measured frames"),
                  whole("warmup", "K", 3, 0, 100000, "unmeasured frames first"),
                  json_option("one JSON object: median_ms (sort + draw), path, and the parts")})};
    return command;
}

Report device_report(const gpu::DeviceCaps& caps) {
    Report report("render");
    report.json().update({{"device", caps.name}, {"driver", caps.driver}});
    report.line(format("device %s (%s)", caps.name.c_str(), caps.driver.c_str()));
    return report;
}

// --path meshraster: the lit mesh the paper compares against, with about as many vertices.
Outcome measure_mesh_raster(gpu::Context& ctx, const Options& opt, const render::FrameInputs& frame) {
    const uint32_t count = opt.whole("splats"), width = opt.whole("width"), height = opt.whole("height");
    const uint32_t repeat = opt.whole("repeat");
    auto r = bench_mesh_raster(ctx, count, frame, width, height, opt.whole("warmup"), repeat);
    if (!r.ok()) return r.error();
    PBDSPLAT_TRY(check_validation(ctx));
    Report report = device_report(ctx.caps());
    report.json().update({{"path", "meshraster"}, {"splats", count}, {"vertices", r->vertices}, {"triangles", r->triangles},
                          {"environment", opt.text("environment")}, {"width", width}, {"height", height}, {"repeat", repeat},
                          {"median_ms", r->median_ms}});
    report.figures(format("mesh raster of an icosphere (%zu vertices, %zu triangles) at %ux%u, median of %u frames:", r->vertices,
                          r->triangles, width, height, repeat),
                   {{"draw", r->median_ms, "ms GPU"}});
    return report;
}

// --ply FILE: a trained capture orbited as `render FILE.ply` draws it. Each frame turns the eye
// about the file's vertical axis, sorts far to near (on the device or the CPU, as render does)
// and draws.
Outcome measure_capture(const Options& opt) {
    for (const char* key : {"splats", "shading", "footprint", "blend", "kappa", "carrier", "cull-facing", "environment", "scale"})
        if (opt.given(key)) return Outcome::usage(std::string("--") + key + " applies to the sphere; --ply draws the file as it was trained");
    const std::string file = opt.text("ply");
    const uint32_t width = opt.whole("width"), height = opt.whole("height");
    const uint32_t repeat = opt.whole("repeat"), warmup = opt.whole("warmup");
    const core::Stopwatch load_clock;
    auto gaussians = splat::read_ply_gaussians(file, splat::PlyUp::minus_y, splat::MissingNormals::leave);
    if (!gaussians.ok()) return gaussians.error();
    const double load_ms = load_clock.elapsed_ms();
    if (gaussians->records.empty()) return core::make_error(file + ": holds no Gaussians");

    auto ctx = open_context(opt);
    if (!ctx.ok()) return ctx.error();
    const gpu::DeviceCaps& caps = ctx.value()->caps();
    if (!caps.timestamps) return core::make_error("device '" + caps.name + "' has no timestamp queries to measure with");
    const std::string& sort_arg = opt.text("sort");
    if (opt.given("sort") && sort_arg == "off") return Outcome::usage("--sort off: a capture is drawn far to near; give cpu or gpu");
    const bool gpu_sort = opt.given("sort") ? sort_arg == "gpu" : scene::ply_sort_on_gpu(caps.type);
    render::RendererOptions options = scene::ply_renderer_options(gaussians.value(), width, height, gpu_sort);
    const std::string& path_arg = opt.text("path");
    if (path_arg == "meshraster") return Outcome::usage("--path meshraster draws the sphere's mesh, not a capture");
    options.path = core::from_name<render::SplatPath>(render::k_splat_path_names, path_arg);  // none: auto
    if (options.path) {
        const std::string why = render::splat_path_unsupported(caps, *options.path);
        if (!why.empty()) return core::make_error(why);
    }
    auto renderer = passes::OffscreenRenderer::create(*ctx.value(), options);
    if (!renderer.ok()) return renderer.error();

    const render::FrameInputs start = scene::ply_view(gaussians->records);
    const Vec3f offset = start.camera.eye - start.camera.target;
    std::vector<double> draw, sort_ms, wall;
    for (uint32_t i = 0; i < warmup + repeat; ++i) {
        const core::Stopwatch frame_clock;
        render::FrameInputs frame = start;
        const float turn = 2.0f * float(M_PI) * float(i) / float(warmup + repeat);
        frame.camera.eye = start.camera.target + Vec3f(std::cos(turn) * offset.x() + std::sin(turn) * offset.z(), offset.y(),
                                                       -std::sin(turn) * offset.x() + std::cos(turn) * offset.z());
        const core::Stopwatch sort_clock;
        scene::order_ply(gaussians.value(), frame, gpu_sort);
        const double sorting = sort_clock.elapsed_ms();
        PBDSPLAT_TRY(renderer.value()->render(gaussians->records, frame, {}, gaussians->shapes, gaussians->sh));
        PBDSPLAT_TRY(renderer.value()->finish());
        if (i < warmup) continue;
        draw.push_back(renderer.value()->timings().draw_ms);
        sort_ms.push_back(gpu_sort ? renderer.value()->timings().sort_ms : sorting);
        wall.push_back(frame_clock.elapsed_ms());
    }
    PBDSPLAT_TRY(check_validation(*ctx.value()));
    const size_t count = gaussians->records.size();
    const uint32_t degree = gaussians->sh.empty() ? 0 : gaussians->sh_degree;
    const bool anisotropic = !gaussians->shapes.empty();
    Report report = device_report(caps);
    report.json().update({{"ply", file}, {"gaussians", count}, {"anisotropic", anisotropic}, {"sh_degree", degree},
                          {"path", render::splat_path_name(options.path.value_or(render::best_splat_path(caps, anisotropic)))},
                          {"sort", gpu_sort ? "gpu" : "cpu"}, {"width", width}, {"height", height}, {"repeat", repeat}, {"load_ms", load_ms},
                          {"median_ms", core::median(wall)}, {"draw_ms", core::median(draw)}, {"sort_ms", core::median(sort_ms)},
                          {"frame_wall_ms", core::median(wall)}});
    report.line(format("%zu %s Gaussians (colour of degree %u) from %s at %ux%u, an orbit of %u frames, median:", count,
                       anisotropic ? "anisotropic" : "round", degree, file.c_str(), width, height, repeat));
    report.figures("", {{"read", load_ms, "ms CPU (once: the file, no normals estimated)"},
                        {"sort", core::median(sort_ms),
                         gpu_sort ? "ms GPU (cull, radix sort, gather; the streams found through its order)"
                                  : "ms CPU (far to near, with the shape and colour streams)"},
                        {"draw", core::median(draw), "ms GPU (upload excluded)"},
                        {"frame", core::median(wall), "ms wall (sort, upload, draw, readback)"}});
    return report;
}

Outcome measure(const Options& opt) {
    if (opt.given("ply")) return measure_capture(opt);
    const uint32_t count = opt.whole("splats"), width = opt.whole("width"), height = opt.whole("height");
    const uint32_t repeat = opt.whole("repeat"), warmup = opt.whole("warmup");
    const std::string& path_arg = opt.text("path");
    const bool mesh_raster = path_arg == "meshraster";
    const std::optional<render::SplatPath> path = core::from_name<render::SplatPath>(render::k_splat_path_names, path_arg);
    const std::string& sort = opt.text("sort");
    if (mesh_raster && sort != "off") return Outcome::usage("--path meshraster draws opaque triangles: no --sort");
    const std::string& shading_arg = opt.text("shading");
    const std::string& footprint_arg = opt.text("footprint");
    const bool normalised = opt.text("blend") == "normalised";
    if (normalised && footprint_arg != "gaussian")
        return Outcome::usage("--blend normalised weighs each splat by its Gaussian falloff: add --footprint gaussian");
    if (normalised && sort != "off") return Outcome::usage("--blend normalised does not depend on the order: no --sort");
    const std::string& carrier_arg = opt.text("carrier");
    const float kappa = opt.real("kappa"), cull_facing = opt.real("cull-facing"), scale = opt.real("scale");
    const render::EnvSampling environment = *render::env_sampling_from_name(opt.text("environment"));

    auto ctx = open_context(opt);
    if (!ctx.ok()) return ctx.error();
    const gpu::DeviceCaps& caps = ctx.value()->caps();
    if (!caps.timestamps) return core::make_error("device '" + caps.name + "' has no timestamp queries to measure with");
    if (path) {
        const std::string why = render::splat_path_unsupported(caps, *path);
        if (!why.empty()) return core::make_error(why);
    }

    auto [records, frame] = make_splat_sphere(count);
    frame.lighting.environment.sampling = environment;
    frame.style.scale_multiplier = scale;
    frame.style.footprint = footprint_arg == "paper" ? render::Footprint::paper : render::Footprint::gaussian;
    frame.style.kappa = kappa;
    if (normalised) frame.style.blend = render::Blend::normalised;
    frame.style.cull_facing = cull_facing;
    // Screens of carrier area drawn: each quad spans twice the splat's reach at its distance
    // (about 3.5 here).
    const float sigma = splat::half_to_float(records.front().scale_half);
    const float pixels_per_unit = float(height) / (2.0f * 3.5f * std::tan(math::radians(frame.camera.fov_y_degrees) * 0.5f));
    const float quad_side = 2.0f * render::splat_reach_bound(frame.style) * sigma * pixels_per_unit;
    const double screens = double(quad_side) * quad_side * count / (double(width) * height);
    if (mesh_raster) return measure_mesh_raster(*ctx.value(), opt, frame);
    if (sort == "cpu") frame.style.order = render::SplatOrder::cpu;
    if (sort == "gpu") frame.style.order = render::SplatOrder::gpu;
    render::RendererOptions options;
    options.gpu_sort = sort == "gpu";
    options.shading = shading_arg == "corner" ? render::SplatShading::corner : render::SplatShading::fragment;
    options.carrier = carrier_arg == "octagon" ? render::SplatCarrier::octagon : render::SplatCarrier::quad;
    options.width = width;
    options.height = height;
    options.max_splats = count;
    options.frames_in_flight = 1;
    options.path = path;
    options.normalised = normalised;
    auto renderer = passes::OffscreenRenderer::create(*ctx.value(), options);
    if (!renderer.ok()) return renderer.error();
    const render::SplatPath used = path.value_or(render::best_splat_path(caps));

    splat::SortScratch scratch;
    const Mat4f view = math::look_at(frame.camera.eye, frame.camera.target, frame.camera.up);
    std::vector<double> draw, sort_ms, gpu_sort_ms, wall;
    for (uint32_t i = 0; i < warmup + repeat; ++i) {
        const core::Stopwatch frame_clock;
        double sorting = 0.0;
        if (sort == "cpu") {
            const core::Stopwatch clock;
            splat::sort_far_to_near(records, view, scratch);
            sorting = clock.elapsed_ms();
        }
        PBDSPLAT_TRY(renderer.value()->render(records, frame));
        PBDSPLAT_TRY(renderer.value()->finish());
        if (i < warmup) continue;
        draw.push_back(renderer.value()->timings().draw_ms);
        gpu_sort_ms.push_back(renderer.value()->timings().sort_ms);
        sort_ms.push_back(sorting);
        wall.push_back(frame_clock.elapsed_ms());
    }
    PBDSPLAT_TRY(check_validation(*ctx.value()));
    const double median_ms = core::median(draw) + core::median(sort_ms) + core::median(gpu_sort_ms);
    Report report = device_report(caps);
    report.json().update({{"splats", count}, {"path", render::splat_path_name(used)}, {"sort", sort},
                          {"environment", render::env_sampling_name(environment)}, {"shading", shading_arg},
                          {"footprint", footprint_arg}, {"blend", opt.text("blend")}, {"kappa", kappa}, {"carrier", carrier_arg}, {"cull_facing", cull_facing},
                          {"scale", scale}, {"quad_screens", screens}, {"width", width}, {"height", height}, {"repeat", repeat},
                          {"median_ms", median_ms}, {"draw_ms", core::median(draw)}, {"sort_ms", core::median(sort_ms)},
                          {"gpu_sort_ms", core::median(gpu_sort_ms)}, {"frame_wall_ms", core::median(wall)}});
    report.line(format("%u splats at %ux%u, path %s, sort %s, shading per %s, median of %u frames:", count, width, height,
                       render::splat_path_name(used), sort.c_str(), shading_arg.c_str(), repeat));
    report.line(format("footprint %s, blend %s, carrier %s, %.1f screens of carrier area", footprint_arg.c_str(), opt.text("blend").c_str(),
                       carrier_arg.c_str(), screens));
    const bool two_passes = sort == "off" && footprint_arg == "gaussian";
    const char* passes = normalised ? "ms GPU (visibility, sums, resolve)" : two_passes ? "ms GPU (visibility + colour passes)" : "ms GPU (one pass)";
    std::vector<Figure> figures = {{"draw", core::median(draw), passes}};
    if (sort == "cpu") figures.push_back({"sort", core::median(sort_ms), "ms CPU"});
    if (sort == "gpu") figures.push_back({"sort", core::median(gpu_sort_ms), "ms GPU (cull, radix sort, gather)"});
    figures.push_back({"frame", core::median(wall), "ms wall (upload, draw, readback)"});
    report.figures("", figures);
    return report;
}

} // namespace

const BenchSuite k_bench_render{"render", "splat pass ms per frame by path (gs, mesh, vertex, meshraster), sort, shading",
                                command_spec, measure};

} // namespace pbdsplat::cli
