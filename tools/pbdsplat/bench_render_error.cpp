#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "core/timer.h"
#include "pbdsplat/bench_suites.h"
#include "pbdsplat/gpu_options.h"
#include "pbdsplat/splat_sphere.h"
#include "pbdsplat/svg_plot.h"
#include "passes/offscreen_renderer.h"
#include "splat/sort.h"

namespace pbdsplat::cli {
namespace {

struct Variant {
    std::string name;
    render::SplatPath path = render::SplatPath::geometry;
    render::SplatOrder order = render::SplatOrder::unsorted;
    render::SplatShading shading = render::SplatShading::fragment;
    float kappa = 0.0f, scale = 1.0f;  // kappa 0: the footprint's default
    // Splats per area against the reference's: the sampling density that eta sets (spacing h =
    // eta * edge length, so density ~ 1 / eta^2); each splat's size follows its spacing.
    float density = 1.0f;
    render::Footprint footprint = render::Footprint::gaussian;
};

struct Measured {
    Variant v;
    double ms = 0.0, psnr = 0.0, share_over = 0.0;
};

// Renders `records` `repeat` times; the image and the median GPU ms (sort + draw, plus the
// CPU sort where the order is the CPU's).
core::Result<std::pair<core::ImageRgba8, double>> render(gpu::Context& ctx, std::vector<splat::GaussianRecord> records,
                                                        render::FrameInputs frame, const Variant& v, uint32_t w, uint32_t h,
                                                        uint32_t repeat) {
    render::RendererOptions o;
    o.width = w;
    o.height = h;
    o.path = v.path;
    o.shading = v.shading;
    o.max_splats = uint32_t(records.size());
    o.frames_in_flight = 1;
    o.gpu_sort = v.order == render::SplatOrder::gpu;
    frame.style.order = v.order;
    frame.style.footprint = v.footprint;
    frame.style.kappa = v.kappa;
    frame.style.scale_multiplier = v.scale;
    auto r = passes::OffscreenRenderer::create(ctx, o);
    if (!r.ok()) return r.error();
    std::vector<double> ms;
    core::ImageRgba8 image;
    splat::SortScratch scratch;
    const Mat4f view = math::look_at(frame.camera.eye, frame.camera.target, frame.camera.up);
    for (uint32_t i = 0; i < repeat + 1; ++i) {
        const core::Stopwatch clock;
        if (v.order == render::SplatOrder::cpu) splat::sort_far_to_near(records, view, scratch);
        const double sort_ms = clock.elapsed_ms();
        PBDSPLAT_TRY(r.value()->render(records, frame));
        auto img = r.value()->finish();
        if (!img.ok()) return img.error();
        image = std::move(img).value();
        if (i > 0) ms.push_back(sort_ms + r.value()->timings().sort_ms + r.value()->timings().draw_ms);  // the first warms up
    }
    return std::pair{std::move(image), core::median(ms)};
}

const CommandSpec& command_spec() {
    static const CommandSpec command{
        "bench render-error", "",
        "Rendering, time against error: N splats on a sphere rendered in each footprint (the paper's\n"
        "disc, the Gaussian) by every path the device has, unsorted and sorted (CPU, GPU), shaded per\n"
        "fragment and per corner, and with other cut-offs (kappa), sampling densities (eta) and splat\n"
        "scales; each image against a reference of its footprint (geometry shader, sorted on the CPU,\n"
        "per-fragment shading, rendered at 4x the resolution and averaged down). Prints the\n"
        "median GPU ms (sort + draw) of R frames, the PSNR and the share of pixels off by more than\n"
        "2/255, and writes DIR/render_error.csv and DIR/render_error.svg.\n",
        with_gpu({whole("splats", "N", 10000, 1, 1u << 22, "splats on the sphere"),
                  whole("width", "W", 480, 16, 4096, "image width"), whole("height", "H", 270, 16, 4096, "image height"),
                  whole("repeat", "R", 3, 1, 1000, "measured frames per variant"), out_dir_option(),
                  json_option("one JSON object: the reference and every variant")})};
    return command;
}

Outcome measure(const Options& opt) {
    const uint32_t count = opt.whole("splats"), w = opt.whole("width"), h = opt.whole("height"), repeat = opt.whole("repeat");
    auto ctx = open_context(opt);
    if (!ctx.ok()) return ctx.error();
    const gpu::DeviceCaps& caps = ctx.value()->caps();

    auto [records, frame] = make_splat_sphere(count);
    // One reference per footprint: the disc's hard rims and the Gaussian's soft ones are
    // different images by design; each is judged against its own supersampled truth.
    core::ImageRgba8 truth[2];
    double reference_ms = 0.0;
    for (const render::Footprint f : {render::Footprint::gaussian, render::Footprint::paper}) {
        Variant reference_variant{"reference", render::SplatPath::geometry, render::SplatOrder::cpu};
        reference_variant.footprint = f;
        auto reference = render(*ctx.value(), records, frame, reference_variant, 4 * w, 4 * h, 1);
        if (!reference.ok()) return reference.error();
        truth[int(f)] = core::downsample(reference->first, 4);
        reference_ms += reference->second;
    }

    std::vector<Variant> variants;
    for (const render::SplatPath p : {render::SplatPath::geometry, render::SplatPath::mesh, render::SplatPath::vertex}) {
        if (!render::splat_path_unsupported(caps, p).empty()) {
            std::fprintf(stderr, "bench render-error: SKIPPED path %s: %s\n", render::splat_path_name(p),
                         render::splat_path_unsupported(caps, p).c_str());
            continue;
        }
        for (const render::SplatShading s : {render::SplatShading::fragment, render::SplatShading::corner}) {
            Variant disc{std::string(render::splat_path_name(p)) + ", paper disc, " + (s == render::SplatShading::corner ? "corner" : "fragment"),
                         p, render::SplatOrder::unsorted, s};
            disc.footprint = render::Footprint::paper;
            variants.push_back(disc);
        }
        for (const render::SplatOrder o : {render::SplatOrder::unsorted, render::SplatOrder::cpu, render::SplatOrder::gpu})
            for (const render::SplatShading s : {render::SplatShading::fragment, render::SplatShading::corner})
                variants.push_back({std::string(render::splat_path_name(p)) + ", sort " + render::splat_order_name(o) + ", " +
                                        (s == render::SplatShading::corner ? "corner" : "fragment"),
                                    p, o, s});
    }
    for (const float kappa : {2.0f, 2.5f, 3.0f})
        variants.push_back({"gs, sort cpu, kappa " + std::to_string(kappa).substr(0, 3), render::SplatPath::geometry,
                            render::SplatOrder::cpu, render::SplatShading::fragment, kappa});
    for (const float density : {0.5f, 2.0f})
        variants.push_back({std::string("gs, sort cpu, eta x") + (density < 1.0f ? "1.41" : "0.71") + " (density x" +
                                std::to_string(density).substr(0, 3) + ")",
                            render::SplatPath::geometry, render::SplatOrder::cpu, render::SplatShading::fragment, 0.0f, 1.0f,
                            density});
    for (const float scale : {0.7f, 1.4f})
        variants.push_back({"gs, sort cpu, scale " + std::to_string(scale).substr(0, 3), render::SplatPath::geometry,
                            render::SplatOrder::cpu, render::SplatShading::fragment, 0.0f, scale});

    std::vector<Measured> results;
    for (const Variant& v : variants) {
        const auto denser = v.density == 1.0f ? SplatSphere{records, frame}
                                              : make_splat_sphere(std::max<uint32_t>(1, uint32_t(float(count) * v.density)));
        auto r = render(*ctx.value(), denser.records, frame, v, w, h, repeat);
        if (!r.ok()) return core::make_error(v.name + ": " + r.error().to_string());
        auto diff = core::compare_images(r->first, truth[int(v.footprint)], 2);
        if (!diff.ok()) return diff.error();
        results.push_back({v, r->second, diff->psnr_db, diff->share_over});
    }
    PBDSPLAT_TRY(check_validation(*ctx.value()));

    Table table({{"variant", 0, true, ""},
                 {"footprint", 0, false},
                 {"path", 0, false},
                 {"sort", 0, false},
                 {"shading", 0, false},
                 {"kappa", 1, false},
                 {"scale", 1, false},
                 {"density", 1, false},
                 {"ms", 2, true, "GPU ms"},
                 {"psnr_db", 2, true, "PSNR dB"},
                 {"share_over_2", 4, true, "share > 2/255"}});
    for (const Measured& m : results)
        table.add({m.v.name, render::footprint_name(m.v.footprint), render::splat_path_name(m.v.path), render::splat_order_name(m.v.order),
                   m.v.shading == render::SplatShading::corner ? "corner" : "fragment", m.v.kappa, m.v.scale, m.v.density, m.ms,
                   std::isfinite(m.psnr) ? m.psnr : 999.0, m.share_over});
    PlotSpec plot;
    plot.title = "Rendering: time against error (" + std::to_string(count) + " splats, " + std::to_string(w) + "x" +
                 std::to_string(h) + ", against a 4x supersampled sorted reference)";
    plot.x_label = "GPU ms per frame (sort + draw)";
    plot.y_label = "PSNR (dB)";
    plot.log_y = false;
    for (const render::SplatPath p : {render::SplatPath::geometry, render::SplatPath::mesh, render::SplatPath::vertex}) {
        PlotSeries s;
        s.name = render::splat_path_name(p);
        for (const Measured& m : results)
            if (m.v.path == p && std::isfinite(m.psnr)) {
                s.x.push_back(m.ms);
                s.y.push_back(m.psnr);
                s.labels.push_back(m.v.name.substr(m.v.name.find(',') + 2));
            }
        if (!s.x.empty()) plot.series.push_back(s);
    }

    Report report("render-error");
    nlohmann::json variants_json = nlohmann::json::array();
    for (const Measured& m : results)
        variants_json.push_back({{"name", m.v.name}, {"footprint", render::footprint_name(m.v.footprint)}, {"ms", m.ms},
                                 {"psnr_db", std::isfinite(m.psnr) ? m.psnr : 999.0}, {"share_over_2", m.share_over}});
    report.json().update({{"device", caps.name}, {"splats", count}, {"width", w}, {"height", h}, {"reference_ms", reference_ms},
                          {"variants", variants_json}});
    report.table(format("%u splats at %ux%u on %s; reference per footprint: gs, CPU-sorted, per fragment, 4x supersampled "
                        "(PSNR 999: identical)",
                        count, w, h, caps.name.c_str()),
                 table);
    report.csv("render_error.csv", table);
    report.plot("render_error.svg", plot);
    return report;
}

} // namespace

const BenchSuite k_bench_render_error{"render-error", "rendering time against image error, against a supersampled reference",
                                      command_spec, measure};

} // namespace pbdsplat::cli
