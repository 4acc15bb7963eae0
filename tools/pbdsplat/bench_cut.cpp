#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "core/timer.h"
#include "mesh/mesh_spec.h"
#include "pbdsplat/args.h"
#include "pbdsplat/commands.h"
#include "sim/solver.h"
#include "topology/cut.h"

namespace pbdsplat::cli {

namespace {
double stage_a_ms(sim::SoftBody body, int frames) {
    sim::Solver solver;
    sim::SolverSettings s;
    std::vector<double> ms;
    for (int f = 0; f < frames; ++f) {
        const core::Stopwatch clock;
        solver.step(body, 1.0f / 60.0f, s, {}, {});
        ms.push_back(clock.elapsed_ms());
    }
    return core::median(ms);
}
} // namespace

int bench_cut(const std::vector<std::string>& argv) {
    static constexpr const char* help =
        "usage: pbdsplat bench cut [--mesh SPEC] [--cuts N] [--policy cap|burst|rebase] [--frames F] [--json]\n"
        "\n"
        "The cost of one line cut through the middle of a body at rest (paper section 5.7): N cuts,\n"
        "each on a fresh copy of the body along a plane through its centre at a different angle,\n"
        "median milliseconds of the cut (and of rebuilding the solver's derived data inside it),\n"
        "the crossed region, and Stage A ms per frame (paper solver defaults, median of F frames)\n"
        "before and after the first cut; then the cost per crossed triangle and the median ms of\n"
        "each step of the cut, in the order run. Each copy gets the spare capacity a live body\n"
        "keeps from its earlier edits (sim::reserve_headroom), outside the timing.\n"
        "\n"
        "  --mesh SPEC     default teapot.obj (from ../shared/models); procedural specs work too\n"
        "  --cuts N        default 20\n"
        "  --policy P      volume policy of the cut (default cap)\n"
        "  --frames F      Stage A frames timed before and after (default 30)\n"
        "  --json          print one JSON object on stdout\n";
    auto args = Args::parse(argv, {"help", "json"}, {"mesh", "cuts", "policy", "frames"});
    if (!args.ok()) return usage_error("bench cut", args.error().to_string());
    if (args->has("help")) return std::fputs(help, stdout), 0;
    auto cuts = args->get_uint("cuts", 20, 1, 10000);
    auto frames = args->get_uint("frames", 30, 1, 10000);
    if (!cuts.ok()) return usage_error("bench cut", cuts.error().to_string());
    if (!frames.ok()) return usage_error("bench cut", frames.error().to_string());
    topology::CutOptions options;
    const std::string policy = args->get_or("policy", "cap");
    if (policy == "cap") options.volume = topology::VolumePolicy::cap;
    else if (policy == "burst") options.volume = topology::VolumePolicy::burst;
    else if (policy == "rebase") options.volume = topology::VolumePolicy::rebase;
    else return usage_error("bench cut", "--policy must be cap, burst or rebase, not '" + policy + "'");

    const std::string spec = args->get_or("mesh", "teapot.obj");
    auto repaired = mesh::load_mesh_spec(spec);
    if (!repaired.ok()) return fail("bench cut", repaired.error().to_string());
    auto made = sim::make_soft_body(repaired->mesh, {});
    if (!made.ok()) return fail("bench cut", made.error().to_string());
    const sim::SoftBody& body = made.value();
    Vec3f centre = Vec3f::Zero();
    for (const Vec4f& x : body.particles.x) centre += x.head<3>();
    centre /= float(body.particle_count());

    std::vector<double> ms, rebuild_ms;
    std::vector<double> crossed, after;
    std::vector<const char*> phase_names;
    std::vector<std::vector<double>> phase_ms;
    sim::SoftBody first_cut;
    for (uint32_t k = 0; k < cuts.value(); ++k) {
        sim::SoftBody b = body;  // copied outside the timing
        // A copy has no spare capacity; a live body keeps the room its edits grew (amortised).
        sim::reserve_headroom(b);
        const float a = float(k) * 3.14159265f / float(cuts.value());
        auto plane = topology::plane_cut(centre, Vec3f(std::cos(a), 0.3f, std::sin(a)));
        if (!plane.ok()) return fail("bench cut", plane.error().to_string());
        auto change = topology::cut(b, plane.value(), options);
        if (!change.ok()) return fail("bench cut", change.error().to_string());
        ms.push_back(change->ms);
        rebuild_ms.push_back(change->rebuild_ms);
        crossed.push_back(double(change->crossed_triangles));
        after.push_back(double(change->particles_after));
        for (size_t p = 0; p < change->phases.size(); ++p) {
            if (p == phase_names.size()) phase_names.push_back(change->phases[p].name), phase_ms.emplace_back();
            phase_ms[p].push_back(change->phases[p].ms);
        }
        if (k == 0) first_cut = std::move(b);
    }
    const double before_ms = stage_a_ms(body, int(frames.value()));
    const double after_ms = stage_a_ms(first_cut, int(frames.value()));
    nlohmann::json phases = nlohmann::json::array();
    for (size_t p = 0; p < phase_names.size(); ++p) phases.push_back({{"name", phase_names[p]}, {"median_ms", core::median(phase_ms[p])}});
    const double median_crossed = core::median(crossed);
    const nlohmann::json j = {{"suite", "cut"},
                              {"mesh", spec},
                              {"policy", policy},
                              {"cuts", cuts.value()},
                              {"particles_before", body.particle_count()},
                              {"triangles_before", body.triangles.size()},
                              {"particles_after", core::median(after)},
                              {"crossed_triangles", core::median(crossed)},
                              {"median_cut_ms", core::median(ms)},
                              {"median_rebuild_ms", core::median(rebuild_ms)},
                              {"us_per_crossed_triangle", median_crossed > 0.0 ? 1000.0 * core::median(ms) / median_crossed : 0.0},
                              {"phases", phases},
                              {"stage_a_ms_before", before_ms},
                              {"stage_a_ms_after", after_ms}};
    if (args->has("json")) {
        std::printf("%s\n", j.dump().c_str());
        return 0;
    }
    std::printf("%s: %zu particles, %zu triangles; %u cuts through the centre (%s)\n", spec.c_str(), body.particle_count(),
                body.triangles.size(), cuts.value(), policy.c_str());
    std::printf("  crossed triangles %.0f, particles after %.0f\n", core::median(crossed), core::median(after));
    std::printf("  cut %.3f ms (median), of which derived solver data %.3f ms\n", core::median(ms), core::median(rebuild_ms));
    if (median_crossed > 0.0) std::printf("  %.2f us per crossed triangle\n", 1000.0 * core::median(ms) / median_crossed);
    for (size_t p = 0; p < phase_names.size(); ++p) std::printf("    %-22s %8.3f ms\n", phase_names[p], core::median(phase_ms[p]));
    std::printf("  Stage A %.3f ms/frame before, %.3f ms/frame after the cut\n", before_ms, after_ms);
    return 0;
}

} // namespace pbdsplat::cli
