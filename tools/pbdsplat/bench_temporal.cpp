#include <cmath>

#include <nlohmann/json.hpp>

#include "pbdsplat/bench_suites.h"
#include "pbdsplat/gpu_options.h"
#include "pbdsplat/scene_arg.h"
#include "pbdsplat/svg_plot.h"
#include "scene/scene_runtime.h"

namespace pbdsplat::cli {
namespace {

double mean(const std::vector<double>& v) {
    double s = 0.0;
    for (double x : v) s += x;
    return v.empty() ? 0.0 : s / double(v.size());
}

const CommandSpec& command_spec() {
    static const CommandSpec command{
        "bench temporal", "[SCENE.toml]",
        "Temporal stability (the paper's \"no flicker\", measured): runs the scene (default: the\n"
        "built-in one, whose camera orbits slowly and which is cut at 5 s) and, for frames F to\n"
        "F + N, renders the splats and the lit mesh of the same body from the same camera. Prints\n"
        "the mean absolute luminance change between consecutive frames (0..1) for each, away from\n"
        "any cut and within 5 frames of one, and writes DIR/temporal.csv and DIR/temporal.svg.\n",
        with_gpu({whole("from", "F", 240, 0, 1000000, "first measured frame (the default scene's cut is at 300)"),
                  whole("frames", "N", 120, 2, 100000, "measured frames"),
                  whole("width", "W", 320, 16, 4096, "image width"), whole("height", "H", 180, 16, 4096, "image height"),
                  out_dir_option(), json_option()})};
    return command;
}

Outcome measure(const Options& opt) {
    const uint32_t from = opt.whole("from"), frames = opt.whole("frames"), width = opt.whole("width"), height = opt.whole("height");
    auto scene = load_scene_arg(opt.operands());
    if (!scene.ok()) return scene.error();
    scene->render.width = width;
    scene->render.height = height;
    auto ctx = open_context(opt);
    if (!ctx.ok()) return ctx.error();

    scene::RuntimeOptions ro;
    ro.gpu = ctx.value().get();
    ro.frames_in_flight = 1;
    auto rt = scene::SceneRuntime::create(scene.value(), ro);
    if (!rt.ok()) return rt.error();
    scene::SceneRuntime& runtime = *rt.value();
    struct Row {
        uint64_t frame;
        double splats, mesh;
        size_t cuts;
    };
    std::vector<Row> rows;
    core::ImageRgba8 last_splats, last_mesh;
    const uint64_t end = uint64_t(from) + frames;
    for (uint64_t f = 0; f < end; ++f) {
        PBDSPLAT_TRY(runtime.step());
        if (f < from) continue;
        auto splats = runtime.finish();
        if (!splats.ok()) return splats.error();
        auto mesh = runtime.mesh_image();  // the runtime's own mesh view, from the same frame inputs
        if (!mesh.ok()) return mesh.error();
        if (!last_splats.pixels.empty())
            rows.push_back({f, core::mean_luminance_change(splats.value(), last_splats).value(),
                            core::mean_luminance_change(mesh.value(), last_mesh).value(), runtime.stats().cuts});
        last_splats = std::move(splats).value();
        last_mesh = std::move(mesh).value();
    }
    PBDSPLAT_TRY(check_validation(*ctx.value()));

    // Frames within 5 of a change in the cut count are "around a cut".
    std::vector<double> calm_splats, calm_mesh, cut_splats, cut_mesh;
    for (size_t i = 0; i < rows.size(); ++i) {
        bool near_cut = false;
        for (size_t k = (i >= 5 ? i - 5 : 0); k < std::min(rows.size(), i + 6); ++k)
            if (k > 0 && rows[k].cuts != rows[k - 1].cuts) near_cut = true;
        (near_cut ? cut_splats : calm_splats).push_back(rows[i].splats);
        (near_cut ? cut_mesh : calm_mesh).push_back(rows[i].mesh);
    }
    Table per_frame({{"frame"}, {"splats_mean_abs_dY"}, {"mesh_mean_abs_dY"}, {"cuts"}});
    for (const Row& r : rows) per_frame.add({r.frame, r.splats, r.mesh, r.cuts});
    PlotSpec plot;
    plot.title = "Temporal stability: mean |luminance change| between frames (" + scene->name + ")";
    plot.x_label = "frame";
    plot.y_label = "mean |dY| (0..1)";
    plot.log_x = plot.log_y = false;
    PlotSeries s{"splats", {}, {}, {}}, m{"mesh raster", {}, {}, {}};
    for (const Row& r : rows) {
        s.x.push_back(double(r.frame)), s.y.push_back(r.splats);
        m.x.push_back(double(r.frame)), m.y.push_back(r.mesh);
    }
    plot.series = {s, m};

    Report report("temporal");
    report.json().update({{"scene", scene->name}, {"from", from}, {"frames", rows.size()},
                          {"splats_calm", mean(calm_splats)}, {"mesh_calm", mean(calm_mesh)},
                          {"splats_around_cut", mean(cut_splats)}, {"mesh_around_cut", mean(cut_mesh)},
                          {"frames_around_cut", cut_splats.size()}});
    Table summary({{"frames_of", 0, true, ""}, {"splats", 5}, {"mesh", 5}, {"frames", 0}});
    summary.add({"away from cuts", mean(calm_splats), mean(calm_mesh), calm_splats.size()});
    if (!cut_splats.empty()) summary.add({"around a cut", mean(cut_splats), mean(cut_mesh), cut_splats.size()});
    report.table(format("scene %s, frames %u to %llu, mean |luminance change| between frames (0..1):", scene->name.c_str(), from,
                        static_cast<unsigned long long>(end - 1)),
                 summary);
    report.csv("temporal.csv", per_frame);
    report.plot("temporal.svg", plot);
    return report;
}

} // namespace

const BenchSuite k_bench_temporal{"temporal", "frame-to-frame luminance change (flicker) of splats and mesh, around a cut",
                                  command_spec, measure};

} // namespace pbdsplat::cli
