#include <algorithm>
#include <array>
#include <cmath>

#include "core/timer.h"
#include "pbdsplat/bench_suites.h"
#include "pbdsplat/gpu_options.h"
#include "pbdsplat/progress.h"
#include "pbdsplat/scene_arg.h"
#include "scene/scene_runtime.h"

namespace pbdsplat::cli {
namespace {

const CommandSpec& command_spec() {
    static const CommandSpec command{
        "bench scene", "[SCENE.toml | MODEL]",
        "Runs a scene (default: the built-in one) through its frame graph without writing images and\n"
        "prints the median milliseconds per frame of each stage group and of the whole frame, and the\n"
        "GPU time of each GPU pass from timestamps (the paper's \"GPU Scene\" row).\n",
        with_gpu({whole("frames", "N", 240, 1, 1000000, "frames"), whole("threads", "T", 1, 1, 64, "simulation threads"),
                  flag("passes", "also the median and mean CPU ms of every pass that runs (what culling a pass saves),\n"
                                 "and the density control's ms per 10k boundary particles; on a CPU device each\n"
                                 "frame waits for the last one's drawing first, so its passes have the cores"),
                  flag("before-after", "also the medians before and after the first cut or tear, and the change\n"
                                       "(the paper's Tables 2-4); without --frames it runs until 3 s\n"
                                       "(simulated) after the first one, and fails if none comes within\n"
                                       "10,000 frames"),
                  save_scene_option(), json_option()})};
    return command;
}

// What the frames gave: per stage group and per pass, and the paper's rows split at the first
// topology change (CPU frame, GPU scene, the four update stages).
struct Split {
    std::vector<double> cpu_frame, gpu_scene;
    std::array<std::vector<double>, scene::k_timed_groups> groups;  // per group (scene::k_pass_groups)
    size_t particles = 0, gaussians = 0, frames = 0;
};
struct Samples {
    std::array<std::vector<double>, scene::k_timed_groups> groups;  // per group (scene::k_pass_groups)
    std::vector<double> frame, gpu_upload, gpu_sort, gpu_draw;
    // The splat pass's parts (render::GpuTimings).
    std::vector<double> gpu_splat, gpu_occluders, gpu_over_occluders, gpu_accumulate, gpu_resolve;
    // What the splats' draws did per frame (pipeline statistics; empty without them).
    std::vector<double> splat_primitives, splat_fragments;
    Split before, after;
    std::vector<std::vector<double>> per_pass;  // per kept pass, per frame
    // Frames after the first change, split by whether this frame changed the topology: what a
    // tear or cut costs above the frames around it.
    std::vector<double> changing_cpu, steady_cpu;
    std::vector<std::vector<double>> changing_pass;  // per kept pass, on the frames that changed
    size_t changes_so_far = 0;
    uint32_t run = 0;
    // The density control, per frame: its pass's ms per 10k boundary particles, and whether it
    // resampled or retired anything (the "during inflation" is the span of such frames).
    std::vector<double> density_per_10k;
    std::vector<bool> density_working;
    size_t density_pass = SIZE_MAX;  // index among the kept passes

    void add(const scene::SceneRuntime& runtime) {
        const auto& s = runtime.stats();
        for (size_t g = 0; g < scene::k_timed_groups; ++g) groups[g].push_back(s.groups.ms[g]);
        frame.push_back(s.graph_ms);
        gpu_upload.push_back(s.gpu.upload_ms), gpu_sort.push_back(s.gpu.sort_ms), gpu_draw.push_back(s.gpu.draw_ms);
        gpu_splat.push_back(s.gpu.splat_ms), gpu_occluders.push_back(s.gpu.occluders_ms);
        gpu_over_occluders.push_back(s.gpu.over_occluders_ms), gpu_accumulate.push_back(s.gpu.accumulate_ms);
        gpu_resolve.push_back(s.gpu.resolve_ms);
        if (s.gpu.splat_counts.fragments > 0) {
            splat_primitives.push_back(double(s.gpu.splat_counts.primitives));
            splat_fragments.push_back(double(s.gpu.splat_counts.fragments));
        }
        const auto& pm = runtime.pass_ms();
        if (per_pass.size() < pm.size()) per_pass.resize(pm.size());
        for (size_t k = 0; k < pm.size(); ++k) per_pass[k].push_back(pm[k]);
        if (density_pass < pm.size()) {
            density_per_10k.push_back(pm[density_pass] * 1e4 / double(std::max<size_t>(1, s.boundary_particles)));
            density_working.push_back(s.density.resampled + s.density.retired > 0);
        }
        Split& part = s.cuts + s.tears == 0 ? before : after;
        part.cpu_frame.push_back(s.groups.cpu_total());
        part.gpu_scene.push_back(s.gpu_scene_ms());
        const bool changed = s.cuts + s.tears > changes_so_far;
        if (&part == &after) (changed ? changing_cpu : steady_cpu).push_back(part.cpu_frame.back());
        if (changed) {
            if (changing_pass.size() < pm.size()) changing_pass.resize(pm.size());
            for (size_t k = 0; k < pm.size(); ++k) changing_pass[k].push_back(pm[k]);
        }
        changes_so_far = s.cuts + s.tears;
        for (size_t g = 0; g < scene::k_timed_groups; ++g) part.groups[g].push_back(s.groups.ms[g]);
        part.particles = s.particles, part.gaussians = s.gaussians, ++part.frames;
    }
};

void report_stages(Report& report, const Samples& m, const gpu::DeviceCaps& caps) {
    using core::median;
    auto& stages = report.json()["stages_median_ms"] = nlohmann::json::object();
    std::vector<Figure> cpu;
    for (const auto& n : scene::k_pass_groups) {
        const double ms = median(m.groups[scene::GroupTimes::slot(n.group)]);
        stages[n.key] = ms;
        cpu.push_back({n.label, ms, "ms"});
    }
    cpu.push_back({"frame (wall)", median(m.frame), "ms (waits for the GPU when it is the bottleneck)"});
    report.json()["gpu_median_ms"] = {{"upload", median(m.gpu_upload)},
                                      {"sort", median(m.gpu_sort)},
                                      {"draw", median(m.gpu_draw)},
                                      {"draw_parts",
                                       {{"splat", median(m.gpu_splat)},
                                        {"occluders", median(m.gpu_occluders)},
                                        {"over_occluders", median(m.gpu_over_occluders)},
                                        {"accumulate", median(m.gpu_accumulate)},
                                        {"resolve", median(m.gpu_resolve)}}}};
    report.json()["gpu_timestamps"] = caps.timestamps;
    // Work, not time: the same on a slow or busy machine, so the work guard can hold it.
    if (!m.splat_fragments.empty())
        report.json()["splat_work_median"] = {{"primitives", median(m.splat_primitives)}, {"fragments", median(m.splat_fragments)}};
    report.figures("", cpu);
    if (caps.timestamps) {
        std::vector<Figure> gpu = {{"upload", median(m.gpu_upload), "ms"},
                                   {"sort", median(m.gpu_sort), "ms"},
                                   {"splat pass", median(m.gpu_draw), "ms, of which:"}};
        const std::pair<const char*, const std::vector<double>*> parts[] = {
            {"  splats (or their depth)", &m.gpu_splat}, {"  occluder mesh", &m.gpu_occluders},
            {"  discs over occluders", &m.gpu_over_occluders}, {"  normalised sums", &m.gpu_accumulate},
            {"  normalised resolve", &m.gpu_resolve}};
        for (const auto& [name, samples] : parts)
            if (median(*samples) > 0.0) gpu.push_back({name, median(*samples), "ms"});
        report.figures("GPU Scene (timestamps):", gpu);
        if (!m.splat_fragments.empty())
            report.figures("Splat draws (pipeline statistics, median a frame):",
                           {{"primitives", median(m.splat_primitives), "", 0}, {"fragments shaded", median(m.splat_fragments), "", 0}});
    } else
        report.line("GPU Scene: device '" + caps.name + "' has no timestamp queries");
}

// The density control's cost against its goal (the goal: at most 0.3 ms a frame per 10k
// samples while the surface changes, ~0 when nothing does): per 10k samples, the mean over all
// frames, over the span from its first to its last working frame, and over the frames between
// with nothing to do.
void report_density(Report& report, const Samples& m) {
    if (m.density_per_10k.empty()) return;
    const auto& w = m.density_working;
    const auto first = std::find(w.begin(), w.end(), true);
    const auto last = std::find(w.rbegin(), w.rend(), true);
    std::vector<double> span, idle;
    if (first != w.end()) {
        const size_t a = size_t(first - w.begin()), b = w.size() - size_t(last - w.rbegin());
        span.assign(m.density_per_10k.begin() + ptrdiff_t(a), m.density_per_10k.begin() + ptrdiff_t(b));
    }
    size_t working = 0;
    for (size_t f = 0; f < w.size(); ++f)
        if (w[f]) ++working;
        else idle.push_back(m.density_per_10k[f]);
    report.json()["density_ms_per_10k_samples"] = {{"mean", core::mean(m.density_per_10k)},
                                                   {"mean_working_span", core::mean(span)},
                                                   {"working_span_frames", span.size()},
                                                   {"working_frames", working},
                                                   {"median_idle", core::median(idle)}};
    report.figures("density control per 10k boundary particles (goal <= 0.3 ms while working):",
                   {{"mean, all frames", core::mean(m.density_per_10k), "ms"},
                    {"mean, first to last working frame", core::mean(span), format("ms (%zu frames, %zu working)", span.size(), working)},
                    {"median, frames with nothing to do", core::median(idle), "ms"}});
}

// --passes: every pass's median CPU ms (GPU passes: their recording), culled ones with the reason,
// and the mean: a pass that works one frame in several (the density control's sample check)
// shows there, not in the median.
void report_passes(Report& report, const Samples& m, const graph::FrameGraph& graph) {
    report.json()["passes_median_ms"] = nlohmann::json::object();
    report.json()["passes_mean_ms"] = nlohmann::json::object();
    Table table({{"pass", 0, true, ""}, {"ms", 4}, {"mean_ms", 4, true, "mean"}, {"ms_changing", 4, true, "on cut/tear frames"}, {"culled", 0, true, ""}});
    size_t k = 0;
    for (const auto& p : graph.describe()) {
        if (p.culled) {
            table.add({p.name, nullptr, nullptr, nullptr, "culled: " + p.reason});
        } else if (k < m.per_pass.size()) {
            const double ms = core::median(m.per_pass[k]);
            const double mean = core::mean(m.per_pass[k]);
            report.json()["passes_median_ms"][p.name] = ms;
            report.json()["passes_mean_ms"][p.name] = mean;
            table.add({p.name, ms, mean, k < m.changing_pass.size() ? nlohmann::json(core::median(m.changing_pass[k])) : nlohmann::json(),
                       ""});
            ++k;
        }
    }
    report.table("per pass (median CPU ms; GPU passes: recording):", table);
    report_density(report, m);
}

// --before-after: the paper's Tables 2-4, split at the first cut or tear.
void report_before_after(Report& report, const Samples& m) {
    using core::median;
    // The paper's Table 3 rows: the simulation's stages and the splats' update.
    auto paper_row = [](const scene::PassGroupNames& n) { return n.stage_a || n.group == scene::PassGroup::update; };
    for (const auto& [name, part] : {std::pair<const char*, const Split*>{"before", &m.before}, {"after", &m.after}}) {
        nlohmann::json& j = report.json()[name] = {{"frames", part->frames}, {"particles", part->particles}, {"gaussians", part->gaussians},
                                                  {"cpu_frame_ms", median(part->cpu_frame)}, {"gpu_scene_ms", median(part->gpu_scene)}};
        for (const auto& n : scene::k_pass_groups)
            if (paper_row(n)) j[std::string(n.key) + "_ms"] = median(part->groups[scene::GroupTimes::slot(n.group)]);
    }
    report.json()["change_frames"] = {{"frames", m.changing_cpu.size()}, {"cpu_frame_ms", median(m.changing_cpu)},
                                      {"steady_frames", m.steady_cpu.size()}, {"steady_cpu_frame_ms", median(m.steady_cpu)}};
    Table table({{"stage", 0, true, ""}, {"before", 3}, {"after", 3}, {"delta", 3}, {"delta_percent", 2, true, "delta %"}});
    auto row = [&table](const char* name, const std::vector<double>& b, const std::vector<double>& a) {
        const double mb = median(b), ma = median(a);
        table.add({name, mb, ma, ma - mb, mb > 0 ? 100.0 * (ma - mb) / mb : 0.0});
    };
    row("CPU frame", m.before.cpu_frame, m.after.cpu_frame);
    row("GPU scene", m.before.gpu_scene, m.after.gpu_scene);
    for (const auto& n : scene::k_pass_groups)
        if (paper_row(n)) row(n.label, m.before.groups[scene::GroupTimes::slot(n.group)], m.after.groups[scene::GroupTimes::slot(n.group)]);
    report.table(format("before and after the first cut or tear (%zu -> %zu particles, %zu -> %zu Gaussians; medians, ms):",
                        m.before.particles, m.after.particles, m.before.gaussians, m.after.gaussians),
                 table);
    if (!m.changing_cpu.empty())
        report.line(format("  frames that cut or tore: %zu, CPU frame %.3f ms against %.3f ms on the %zu after without (%+.3f)",
                           m.changing_cpu.size(), median(m.changing_cpu), median(m.steady_cpu), m.steady_cpu.size(),
                           median(m.changing_cpu) - median(m.steady_cpu)));
}

Outcome measure(const Options& opt) {
    const uint32_t frames = opt.whole("frames"), threads = opt.whole("threads");
    const bool before_after = opt.flag("before-after");
    const bool until_after = before_after && !opt.given("frames");  // run until enough frames follow the change
    auto scene = load_scene_arg(opt);
    if (!scene.ok()) return scene.error();
    auto ctx = open_context(opt);
    if (!ctx.ok()) return ctx.error();
    scene::RuntimeOptions options;
    options.gpu = ctx.value().get();
    options.readback = false;
    options.threads = threads;
    auto created = scene::SceneRuntime::create(scene.value(), options);
    if (!created.ok()) return created.error();
    scene::SceneRuntime& runtime = *created.value();

    Samples m;
    {
        size_t k = 0;
        for (const auto& p : runtime.graph().describe())
            if (!p.culled) {
                if (p.name == scene::k_density_pass) m.density_pass = k;
                ++k;
            }
    }
    const uint32_t frames_after = uint32_t(std::ceil(3.0f / std::max(scene->simulation.dt, 1e-6f)));
    constexpr uint32_t k_max_frames = 10000;
    Progress progress("bench scene", until_after ? 0 : frames);
    // A CPU device draws the last frame on the same cores while the next one's CPU passes run:
    // the first passes of each frame were charged for it (the pile's collision loop, 1 % of a
    // profile, read 2.4 ms). Per pass, the frames are kept apart; the frame figures then add up.
    const bool apart = opt.flag("passes") && ctx.value()->caps().type == "cpu";
    for (uint32_t f = 0; until_after ? (m.after.frames < frames_after && f < k_max_frames) : f < frames; ++f) {
        ++m.run;
        if (apart) ctx.value()->device().wait_idle();
        PBDSPLAT_TRY(runtime.step());
        m.add(runtime);
        progress.frame_done(m.run);
    }
    if (before_after && (m.before.frames == 0 || m.after.frames == 0))
        return core::make_error(scene->name + ": no frames " + std::string(m.before.frames == 0 ? "before" : "after") +
                                " the first cut or tear in " + std::to_string(m.run) + " frames" +
                                (until_after ? " (the scene has none)" : "; run longer (--frames) or leave --frames out"));
    PBDSPLAT_TRY(check_validation(*ctx.value()));
    size_t kept = 0, total = 0;
    for (const auto& p : runtime.graph().describe()) ++total, kept += p.culled ? 0 : 1;
    const auto& s = runtime.stats();
    Report report("scene");
    report.json().update({{"scene", scene->name}, {"frames", m.run}, {"particles", s.particles}, {"passes", total},
                          {"passes_run", kept}, {"median_ms", core::median(m.frame)}});
    report.line(format("scene %s: %zu particles, %zu of %zu passes run, median of %u frames:", scene->name.c_str(), s.particles, kept,
                       total, m.run));
    report_stages(report, m, ctx.value()->caps());
    if (opt.flag("passes")) report_passes(report, m, runtime.graph());
    if (before_after) report_before_after(report, m);
    return report;
}

} // namespace

const BenchSuite k_bench_scene{"scene", "a scene through its frame graph: median ms per stage and per frame", command_spec,
                               measure};

} // namespace pbdsplat::cli
