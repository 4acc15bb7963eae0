#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include <nlohmann/json.hpp>

#include "pbdsplat/options.h"
#include "pbdsplat/commands.h"
#include "pbdsplat/gpu_options.h"
#include "pbdsplat/scene_arg.h"
#include "pbdsplat/report.h"
#include "pbdsplat/svg_plot.h"
#include "passes/coverage.h"
#include "scene/scene_runtime.h"

namespace pbdsplat::cli {

int bench_coverage(const std::vector<std::string>& argv) {
    static const CommandSpec command{
        "bench coverage", "[SCENE.toml]",
        "Coverage through a scene's deformation and cuts: runs the scene (default: the built-in one,\n"
        "which deflates to half its volume, re-inflates and is cut at 5 s) three times, with splats\n"
        "at the mesh vertices only, with boundary particles, and with boundary particles and\n"
        "stretch-aware splat scale; every K frames it measures the hole ratio (share of the mesh\n"
        "raster's pixels the splats leave below half alpha) and the silhouette IoU against a raster\n"
        "of the same deformed mesh. Writes DIR/coverage.csv and DIR/coverage.svg.\n",
        with_gpu({whole("frames", "N", 360, 1, 100000, "frames to run"),
                  whole("every", "K", 20, 1, 100000, "measure every K frames"),
                  whole("width", "W", 320, 16, 4096, "image width"), whole("height", "H", 180, 16, 4096, "image height"),
                  out_dir_option(), json_option("one JSON object: per mode, the mean and worst hole ratio and IoU")})};
    const Parsed parsed = parse_command(command, argv);
    if (!parsed.options) return parsed.exit_code;
    const Options& opt = *parsed.options;
    const uint32_t frames = opt.whole("frames"), every = opt.whole("every"), width = opt.whole("width"), height = opt.whole("height");
    auto base = load_scene_arg(opt.operands());
    if (!base.ok()) return fail("bench coverage", base.error().to_string());
    const std::filesystem::path out_dir = opt.text("out-dir");
    auto ctx = open_context(opt);
    if (!ctx.ok()) return fail("bench coverage", ctx.error().to_string());

    struct Sample {
        std::string mode;
        uint64_t frame;
        double holes, iou;
        size_t cuts;
    };
    std::vector<Sample> samples;
    const std::pair<const char*, std::pair<scene::SurfaceMode, bool>> modes[] = {
        {"vertices", {scene::SurfaceMode::vertices, false}},
        {"boundary", {scene::SurfaceMode::boundary, false}},
        {"boundary+stretch", {scene::SurfaceMode::boundary, true}}};
    for (const auto& [name, mode] : modes) {
        scene::Scene sc = base.value();
        sc.surface.mode = mode.first;
        sc.surface.stretch_scale = mode.second;
        scene::RuntimeOptions ro;  // the simulation and mapping only: coverage renders its own images
        ro.keep_records = true;
        auto rt = scene::SceneRuntime::create(sc, ro);
        if (!rt.ok()) return fail("bench coverage", std::string(name) + ": " + rt.error().to_string());
        for (uint64_t f = 0; f < frames; ++f) {
            if (auto s = rt.value()->step(); !s.ok()) return fail("bench coverage", s.error().to_string());
            if ((f + 1) % every != 0) continue;
            const sim::SoftBody& body = rt.value()->body();
            render::FrameInputs frame = sc.render.frame;
            frame.camera = rt.value()->camera();
            auto c = passes::measure_coverage(*ctx.value(), body.particles.x, body.triangles, rt.value()->records(), frame,
                                             width, height);
            if (!c.ok()) return fail("bench coverage", std::string(name) + ", frame " + std::to_string(f) + ": " + c.error().to_string());
            samples.push_back({name, f + 1, c->hole_ratio, c->silhouette_iou, rt.value()->stats().cuts});
        }
    }
    if (auto v = check_validation(*ctx.value()); !v.ok()) return fail("bench coverage", v.error().to_string());

    std::ostringstream csv;
    csv << "mode,frame,hole_ratio,silhouette_iou,cuts\n";
    for (const Sample& s : samples) csv << s.mode << ',' << s.frame << ',' << s.holes << ',' << s.iou << ',' << s.cuts << '\n';
    if (auto s = write_report_file(out_dir, "coverage.csv", csv.str()); !s.ok()) return fail("bench coverage", s.error().to_string());
    PlotSpec plot;
    plot.title = "Coverage through " + base->name + ": hole ratio against the mesh raster";
    plot.x_label = "frame";
    plot.y_label = "hole ratio";
    plot.log_x = false;
    nlohmann::json summary = nlohmann::json::object();
    for (const auto& [name, mode] : modes) {
        PlotSeries series;
        series.name = name;
        double holes_sum = 0.0, holes_max = 0.0, iou_sum = 0.0, iou_min = 1.0;
        size_t n = 0;
        for (const Sample& s : samples) {
            if (s.mode != name) continue;
            series.x.push_back(double(s.frame));
            series.y.push_back(std::max(s.holes, 1e-6));  // a log axis shows "none" at the floor
            holes_sum += s.holes, holes_max = std::max(holes_max, s.holes), iou_sum += s.iou, iou_min = std::min(iou_min, s.iou), ++n;
        }
        plot.series.push_back(series);
        summary[name] = {{"hole_ratio_mean", n ? holes_sum / double(n) : 0.0}, {"hole_ratio_max", holes_max},
                         {"iou_mean", n ? iou_sum / double(n) : 0.0}, {"iou_min", iou_min}, {"samples", n}};
    }
    if (auto s = write_report_file(out_dir, "coverage.svg", render_svg(plot)); !s.ok())
        return fail("bench coverage", s.error().to_string());
    if (opt.flag("json")) {
        const nlohmann::json j = {{"suite", "coverage"}, {"scene", base->name}, {"frames", frames}, {"modes", summary}};
        std::printf("%s\n", j.dump().c_str());
        return 0;
    }
    std::printf("scene %s, %u frames, coverage every %u frames at %ux%u:\n", base->name.c_str(), frames, every,
                width, height);
    for (const auto& [name, mode] : modes) {
        const auto& m = summary[name];
        std::printf("  %-18s holes mean %.4f %%, worst %.4f %%; IoU mean %.3f, lowest %.3f\n", name,
                    100.0 * m["hole_ratio_mean"].get<double>(), 100.0 * m["hole_ratio_max"].get<double>(), m["iou_mean"].get<double>(),
                    m["iou_min"].get<double>());
    }
    std::printf("wrote %s and coverage.svg\n", (out_dir / "coverage.csv").string().c_str());
    return 0;
}

} // namespace pbdsplat::cli
