#include <cmath>

#include <nlohmann/json.hpp>

#include "pbdsplat/bench_suites.h"
#include "pbdsplat/gpu_options.h"
#include "pbdsplat/scene_arg.h"
#include "pbdsplat/svg_plot.h"
#include "passes/coverage.h"
#include "scene/scene_runtime.h"

namespace pbdsplat::cli {

namespace {

const CommandSpec& command_spec() {
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
    return command;
}

Outcome measure(const Options& opt) {
    const uint32_t frames = opt.whole("frames"), every = opt.whole("every"), width = opt.whole("width"), height = opt.whole("height");
    auto base = load_scene_arg(opt.operands());
    if (!base.ok()) return base.error();
    auto ctx = open_context(opt);
    if (!ctx.ok()) return ctx.error();

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
        if (!rt.ok()) return core::make_error(std::string(name) + ": " + rt.error().to_string());
        for (uint64_t f = 0; f < frames; ++f) {
            PBDSPLAT_TRY(rt.value()->step());
            if ((f + 1) % every != 0) continue;
            const sim::SoftBody& body = rt.value()->body();
            render::FrameInputs frame = sc.render.frame;
            frame.camera = rt.value()->camera();
            auto c = passes::measure_coverage(*ctx.value(), body.particles.x, body.triangles, rt.value()->records(), frame,
                                             width, height);
            if (!c.ok()) return core::make_error(std::string(name) + ", frame " + std::to_string(f) + ": " + c.error().to_string());
            samples.push_back({name, f + 1, c->hole_ratio, c->silhouette_iou, rt.value()->stats().cuts});
        }
    }
    PBDSPLAT_TRY(check_validation(*ctx.value()));

    Table per_frame({{"mode"}, {"frame"}, {"hole_ratio"}, {"silhouette_iou"}, {"cuts"}});
    for (const Sample& sample : samples) per_frame.add({sample.mode, sample.frame, sample.holes, sample.iou, sample.cuts});
    PlotSpec plot;
    plot.title = "Coverage through " + base->name + ": hole ratio against the mesh raster";
    plot.x_label = "frame";
    plot.y_label = "hole ratio";
    plot.log_x = false;
    Table summary({{"mode", 0, true, ""}, {"hole_ratio_mean", 5, true, "holes mean"}, {"hole_ratio_max", 5, true, "holes worst"},
                   {"iou_mean", 3, true, "IoU mean"}, {"iou_min", 3, true, "IoU lowest"}, {"samples", 0, false}});
    nlohmann::json modes_json = nlohmann::json::object();
    for (const auto& [name, mode] : modes) {
        PlotSeries series;
        series.name = name;
        double holes_sum = 0.0, holes_max = 0.0, iou_sum = 0.0, iou_min = 1.0;
        size_t n = 0;
        for (const Sample& sample : samples) {
            if (sample.mode != name) continue;
            series.x.push_back(double(sample.frame));
            series.y.push_back(std::max(sample.holes, 1e-6));  // a log axis shows "none" at the floor
            holes_sum += sample.holes, holes_max = std::max(holes_max, sample.holes);
            iou_sum += sample.iou, iou_min = std::min(iou_min, sample.iou), ++n;
        }
        plot.series.push_back(series);
        const double holes_mean = n ? holes_sum / double(n) : 0.0, iou_mean = n ? iou_sum / double(n) : 0.0;
        summary.add({name, holes_mean, holes_max, iou_mean, iou_min, n});
        modes_json[name] = {{"hole_ratio_mean", holes_mean}, {"hole_ratio_max", holes_max}, {"iou_mean", iou_mean},
                            {"iou_min", iou_min}, {"samples", n}};
    }
    Report report("coverage");
    report.json().update({{"scene", base->name}, {"frames", frames}, {"modes", modes_json}});
    report.table(format("scene %s, %u frames, coverage every %u frames at %ux%u (hole ratio 0..1):", base->name.c_str(), frames,
                        every, width, height),
                 summary);
    report.csv("coverage.csv", per_frame);
    report.plot("coverage.svg", plot);
    return report;
}

} // namespace

const BenchSuite k_bench_coverage{"coverage", "hole ratio and silhouette IoU through deformation and cuts, by surface mode",
                                  command_spec, measure};

} // namespace pbdsplat::cli
