#include <cmath>
#include <cstdio>

#include "core/timer.h"
#include "asset/mesh_spec.h"
#include "pbdsplat/bench_suites.h"
#include "pbdsplat/svg_plot.h"
#include "sim/error_metrics.h"
#include "sim/solver.h"
#include "topology/cut.h"

namespace pbdsplat::cli {
namespace {

// Damping (1/s) for every run: the body swings toward its hanging rest instead of oscillating,
// so the comparison at time T measures the solver, not the phase of a swing.
constexpr float k_damping = 2.0f;

struct Run {
    std::string mesh, method;
    uint32_t iterations = 0, substeps = 0;
    double ms_per_frame = 0.0;
    double position_error = 0.0;  // RMS against the reference, over the bounding-box diagonal
    double strain = 0.0;          // mean |length - rest| / rest over the edges
    double volume_error = 0.0;    // |V - k V0| / (k V0), volumes summed over components
};

const CommandSpec& command_spec() {
    static const CommandSpec command{
        "bench sim-error", "",
        "Run time against error for Stage A. Each body hangs from its highest particle under gravity\n"
        "(damping 2/s) with its volume constraint on. For PBD (paper mode) with I in {1,2,5,10,20} and XPBD with\n"
        "S in {1,2,4,8,16} x I=1, it measures the median ms per frame and, after T seconds at 60 Hz,\n"
        "the error against a reference run (XPBD, S=64, double precision): RMS position error over\n"
        "the bounding-box diagonal, mean relative edge strain, relative volume error.\n"
        "Writes DIR/sim_error.csv, DIR/sim_error_position.svg and DIR/sim_error_strain.svg.\n",
        {text("meshes", "LIST", "icosphere:4,teapot.obj,stanford-bunny.obj", "comma-separated mesh specs"),
         real("seconds", "T", 2.0f, 0.1f, 60.0f, "simulated time"),
         flag("after-cut", "first open a slit in each body (a plane cut limited to a ball on its +x side),\n"
                           "so the figures are those after a topology change"),
         out_dir_option(), json_option()}};
    return command;
}

Outcome measure(const Options& opt) {
    const bool after_cut = opt.flag("after-cut");
    const std::string stem = after_cut ? "sim_error_after_cut" : "sim_error";
    const int frames = int(std::lround(opt.real("seconds") * 60.0f));
    const float dt = 1.0f / 60.0f;

    const std::vector<std::string> meshes = split_list(opt.text("meshes"));
    std::vector<Run> runs;
    for (const std::string& spec : meshes) {
        auto repaired = asset::load_mesh_spec(spec);
        if (!repaired.ok()) return repaired.error();
        const float diagonal = mesh::bounds(repaired->mesh).diagonal();
        auto made = sim::make_soft_body(std::move(repaired).value().mesh, {});
        if (!made.ok()) return made.error();
        sim::SoftBody start = std::move(made).value();
        start.pin(start.extreme_particle(1));
        const std::string label = after_cut ? spec + " after a cut" : spec;
        if (after_cut) {
            // A slit across the +x side: the body stays one piece (hanging from its pin) with a
            // new boundary, re-indexed constraints and a capped volume.
            const Vec3f side = sim::xyz(start.particles.x[start.extreme_particle(0)]);
            auto surface = topology::plane_cut(side, Vec3f::UnitY());
            if (!surface.ok()) return surface.error();
            const float r = 0.25f * diagonal;
            surface->inside = [side, r](const Vec3f& x) { return (x - side).squaredNorm() < r * r; };
            auto change = topology::cut(start, surface.value());
            if (!change.ok()) return core::make_error(spec + ": " + change.error().to_string());
        }

        std::fprintf(stderr, "%s: %zu particles, reference (XPBD S=64, double)...\n", spec.c_str(), start.particle_count());
        sim::SoftBodyT<double> reference = sim::to_double(start);
        {
            sim::SolverSettings s;
            s.mode = sim::SolverMode::xpbd;
            s.substeps = 64;
            s.iterations = 1;
            s.damping = k_damping;
            sim::SolverT<double> solver;
            for (int f = 0; f < frames; ++f) solver.step(reference, dt, s, {}, {});
        }
        auto measure = [&](sim::SolverMode mode, uint32_t iterations, uint32_t substeps) {
            sim::SoftBody body = start;
            sim::SolverSettings s;
            s.mode = mode;
            s.iterations = iterations;
            s.substeps = substeps;
            s.damping = k_damping;
            sim::Solver solver;
            std::vector<double> ms;
            for (int f = 0; f < frames; ++f) ms.push_back(solver.step(body, dt, s, {}, {}).total());
            Run r;
            r.mesh = label;
            r.method = mode == sim::SolverMode::xpbd ? "xpbd" : "pbd";
            r.iterations = iterations;
            r.substeps = substeps;
            r.ms_per_frame = core::median(ms);
            r.position_error = sim::rms_position_error(body, reference, double(diagonal));
            r.strain = sim::mean_edge_strain(body);
            r.volume_error = sim::total_volume_error(body);
            std::fprintf(stderr, "  %-4s I=%-2u S=%-2u %8.3f ms/frame  position %.3e  strain %.3e  volume %.3e\n",
                         r.method.c_str(), iterations, substeps, r.ms_per_frame, r.position_error, r.strain, r.volume_error);
            runs.push_back(r);
        };
        for (uint32_t i : {1u, 2u, 5u, 10u, 20u}) measure(sim::SolverMode::paper, i, 1);
        for (uint32_t s : {1u, 2u, 4u, 8u, 16u}) measure(sim::SolverMode::xpbd, 1, s);
        Run ref;
        ref.mesh = label;
        ref.method = "reference";
        ref.iterations = 1;
        ref.substeps = 64;
        ref.strain = sim::mean_edge_strain(reference);
        ref.volume_error = sim::total_volume_error(reference);
        runs.push_back(ref);
    }

    Table table({{"mesh", 0, true, ""},
                 {"method", 0, true, ""},
                 {"iterations", 0, true, "I"},
                 {"substeps", 0, true, "S"},
                 {"ms_per_frame", 3, true, "ms/frame"},
                 {"position_error_rel", -3, true, "position"},
                 {"mean_strain", -3, true, "strain"},
                 {"volume_error_rel", -3, true, "volume"}});
    for (const Run& r : runs)
        table.add({r.mesh, r.method, r.iterations, r.substeps, r.ms_per_frame, r.position_error, r.strain, r.volume_error});
    Report report("sim-error");
    report.json().update({{"frames", frames}, {"runs", table.json()}});
    report.table(format("after %d frames at 60 Hz (errors relative: position to the bounding-box diagonal):", frames), table);
    report.csv(stem + ".csv", table);
    for (const auto& [file, metric, label] :
         {std::tuple{stem + "_position.svg", &Run::position_error, "RMS position error / bounding-box diagonal"},
          std::tuple{stem + "_strain.svg", &Run::strain, "mean relative edge strain"}}) {
        PlotSpec plot;
        plot.title = std::string("Stage A: time against ") + label + " after " + std::to_string(frames) + " frames";
        plot.x_label = "ms per frame (one thread)";
        plot.y_label = label;
        for (const std::string& mesh_spec : meshes)
            for (const char* method : {"pbd", "xpbd"}) {
                const std::string spec = after_cut ? mesh_spec + " after a cut" : mesh_spec;
                PlotSeries series;
                series.name = spec + (std::string(method) == "pbd" ? " PBD (I)" : " XPBD (S)");
                for (const Run& r : runs)
                    if (r.mesh == spec && r.method == method) {
                        series.x.push_back(r.ms_per_frame);
                        series.y.push_back(r.*metric);
                        series.labels.push_back(std::to_string(r.method == "pbd" ? r.iterations : r.substeps));
                    }
                plot.series.push_back(series);
            }
        report.plot(file, plot);
    }
    return report;
}

} // namespace

const BenchSuite k_bench_sim_error{"sim-error", "Stage A run time against error, PBD and XPBD, to CSV and SVG plots", command_spec,
                                   measure};

} // namespace pbdsplat::cli
