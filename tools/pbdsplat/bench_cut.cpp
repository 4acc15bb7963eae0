#include <algorithm>
#include <cmath>
#include <numeric>
#include <cstdio>
#include <random>

#include <nlohmann/json.hpp>

#include "core/timer.h"
#include "asset/mesh_spec.h"
#include "pbdsplat/bench_suites.h"
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

// N cuts through the centre of fresh copies of the body made from `spec`: the figures as JSON.
core::Result<nlohmann::json> measure_cuts(const std::string& spec, uint32_t cuts, uint32_t frames, const topology::CutOptions& options) {
    auto repaired = asset::load_mesh_spec(spec);
    if (!repaired.ok()) return repaired.error();
    auto made = sim::make_soft_body(repaired->mesh, {});
    if (!made.ok()) return made.error();
    // One solver step first, as every body in a scene has had before anyone cuts it: a cut reads
    // a piece's volume from the solver's last measure where it can, and a body never stepped has
    // none (then the cut sums the whole piece, a cost no scene pays).
    {
        sim::Solver solver;
        solver.step(made.value(), 1.0f / 60.0f, sim::SolverSettings{}, {}, {});
    }
    const sim::SoftBody& body = made.value();
    Vec3f centre = Vec3f::Zero();
    for (const Vec4f& x : body.particles.x) centre += x.head<3>();
    centre /= float(body.particle_count());

    std::vector<double> ms, rebuild_ms;
    std::vector<double> crossed, after, searched, swept;
    std::vector<const char*> phase_names;
    std::vector<std::vector<double>> phase_ms;
    sim::SoftBody first_cut, b;
    // Stage A frames of the uncut body, one before each cut: the machine's speed drifts within a
    // run, and the cut's figure is read against these (the work guard). Each follows a cut and
    // finds the caches cold, so it runs slower than the frames of stage_a_ms_before.
    sim::SoftBody stepped = body;
    sim::Solver stepper;
    std::vector<double> step_ms;
    for (uint32_t k = 0; k < cuts; ++k) {
        {
            const core::Stopwatch clock;
            stepper.step(stepped, 1.0f / 60.0f, sim::SolverSettings{}, {}, {});
            step_ms.push_back(clock.elapsed_ms());
        }
        // Copied outside the timing into the same storage each time, as a live body keeps its
        // arrays from frame to frame and the room its edits grew (amortised): a fresh copy's
        // newly mapped pages cost the cut 1.4-2.2x a Stage A frame of icosphere:5 from run to run
        // on one machine, against (see Prober) a steady figure in reused storage.
        b = body;
        sim::reserve_headroom(b);
        const float a = float(k) * 3.14159265f / float(cuts);
        auto plane = topology::plane_cut(centre, Vec3f(std::cos(a), 0.3f, std::sin(a)));
        if (!plane.ok()) return plane.error();
        auto change = topology::cut(b, plane.value(), options);
        if (!change.ok()) return change.error();
        ms.push_back(change->ms);
        rebuild_ms.push_back(change->rebuild_ms);
        crossed.push_back(double(change->crossed_triangles));
        after.push_back(double(change->particles_after));
        searched.push_back(double(change->particles_searched));
        swept.push_back(double(change->searched_whole));
        for (size_t p = 0; p < change->phases.size(); ++p) {
            if (p == phase_names.size()) phase_names.push_back(change->phases[p].name), phase_ms.emplace_back();
            phase_ms[p].push_back(change->phases[p].ms);
        }
        if (k == 0) first_cut = b;
    }
    nlohmann::json phases = nlohmann::json::array();
    for (size_t p = 0; p < phase_names.size(); ++p) phases.push_back({{"name", phase_names[p]}, {"median_ms", core::median(phase_ms[p])}});
    const double median_crossed = core::median(crossed);
    return nlohmann::json{{"mesh", spec},
                          {"particles_before", body.particle_count()},
                          {"triangles_before", body.triangles.size()},
                          {"particles_after", core::median(after)},
                          {"particles_searched", core::median(searched)},
                          {"pieces_swept_whole", core::median(swept)},
                          {"crossed_triangles", median_crossed},
                          {"median_cut_ms", core::median(ms)},
                          {"median_rebuild_ms", core::median(rebuild_ms)},
                          {"us_per_crossed_triangle", median_crossed > 0.0 ? 1000.0 * core::median(ms) / median_crossed : 0.0},
                          {"phases", phases},
                          {"stage_a_ms_before", stage_a_ms(body, int(frames))},
                          {"stage_a_ms_between_cuts", core::median(step_ms)},
                          {"stage_a_ms_after", stage_a_ms(first_cut, int(frames))}};
}

nlohmann::json phases_json(const std::vector<std::string>& names, const std::vector<double>& ms) {
    nlohmann::json phases = nlohmann::json::object();
    for (size_t p = 0; p < names.size(); ++p) phases[names[p]] = ms[p];
    return phases;
}

// The probe of --sequence: the same slit at one particle, cut on 7 copies of a body; its median
// ms and each phase's median. The copies are assigned into one body kept by the caller, as a
// live body keeps its arrays from frame to frame: constructed afresh, a large body's arrays get
// newly mapped pages on every copy, and the cut on them ran at about twice its time on this
// machine (the same slit on the body of 21,808 particles: 0.044-0.051 ms on fresh copies in
// three runs, 0.027-0.040 in reused storage, the small body's 0.023-0.025 either way; no page
// fault inside the cut either way, so the cost is in reaching freshly mapped memory).
struct Probe {
    double ms = 0.0;
    std::vector<std::string> names;
    std::vector<double> phase_ms;
};
struct Prober {
    uint32_t particle = 0;
    float radius = 0.0f;
    topology::CutOptions options;
    core::Result<Probe> on(const sim::SoftBody& body, sim::SoftBody& copy) const {
        std::vector<double> ms;
        Probe out;
        std::vector<std::vector<double>> phase_ms;
        for (int k = 0; k < 7; ++k) {
            copy = body;
            sim::reserve_headroom(copy);
            auto change = topology::cut(copy, topology::local_cut_on(copy, particle, Vec3f::UnitX(), radius), options);
            if (!change.ok()) return change.error();
            ms.push_back(change->ms);
            for (size_t p = 0; p < change->phases.size(); ++p) {
                if (p == out.names.size()) out.names.push_back(change->phases[p].name), phase_ms.emplace_back();
                phase_ms[p].push_back(change->phases[p].ms);
            }
        }
        out.ms = core::median(ms);
        for (const auto& v : phase_ms) out.phase_ms.push_back(core::median(v));
        return out;
    }
};

// The machine's speed drifts over a run of minutes: the two bodies probed again, alternated, so
// what differs between the figures is the body.
core::Result<nlohmann::json> probe_alternated(const Prober& prober, const sim::SoftBody& first, const sim::SoftBody& last) {
    constexpr int k_rounds = 5;
    std::vector<double> at_first, at_last;
    std::vector<std::vector<double>> phases_first, phases_last;
    std::vector<std::string> names;
    sim::SoftBody storage[2];  // each body's copies in storage of their own
    for (int round = 0; round < k_rounds; ++round)
        for (int which = 0; which < 2; ++which) {
            auto q = prober.on(which == 0 ? first : last, storage[which]);
            if (!q.ok()) return q.error();
            (which == 0 ? at_first : at_last).push_back(q->ms);
            auto& phases = which == 0 ? phases_first : phases_last;
            phases.resize(q->phase_ms.size());
            for (size_t k = 0; k < q->phase_ms.size(); ++k) phases[k].push_back(q->phase_ms[k]);
            names = q->names;
        }
    std::vector<double> median_first, median_last;
    for (const auto& v : phases_first) median_first.push_back(core::median(v));
    for (const auto& v : phases_last) median_last.push_back(core::median(v));
    return nlohmann::json{{"rounds", k_rounds},
                          {"after_10_ms", core::median(at_first)},
                          {"after_last_ms", core::median(at_last)},
                          {"ratio", core::median(at_last) / std::max(1e-9, core::median(at_first))},
                          {"phases_after_10_ms", phases_json(names, median_first)},
                          {"phases_after_last_ms", phases_json(names, median_last)}};
}

// --sequence N: N random scalpel cuts one after another on one live body (the long stress suite's
// run), a solver frame between cuts. The cuts land on the southern half; a probe cut (the same
// slit at the north pole, on copies of the body) is timed before the first cut, after the 10th
// and after the last: what the accumulated state (grown arrays, dead slots, moved lists, more
// pieces) adds to one and the same cut.
core::Result<nlohmann::json> measure_sequence(const std::string& spec, uint32_t count, const topology::CutOptions& options) {
    auto repaired = asset::load_mesh_spec(spec);
    if (!repaired.ok()) return repaired.error();
    auto made = sim::make_soft_body(repaired->mesh, {});
    if (!made.ok()) return made.error();
    sim::SoftBody b = std::move(made).value();
    const size_t particles_before = b.particle_count();
    const uint32_t pole = b.extreme_particle(1);
    std::vector<uint32_t> south;
    for (uint32_t i = 0; i < particles_before; ++i)
        if (b.particles.x[i].y() < b.particles.x[pole].y() - 0.6f * (b.particles.x[pole].y() - b.particles.x[b.extreme_particle(1, false)].y()))
            south.push_back(i);
    sim::Solver solver;
    sim::SolverSettings s;
    s.gravity = Vec3f::Zero();
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    // Slits a few edges long (1.5 to 3.5 mean rest edges in radius).
    const float edge = float(b.distance_groups.mean_rest());
    const Prober prober{pole, 2.5f * edge, options};
    nlohmann::json probe_phases = nlohmann::json::array();  // per probe: each phase's median ms
    sim::SoftBody probed;  // the probe's copies, in storage kept between probes
    auto probe = [&]() -> core::Result<double> {
        auto p = prober.on(b, probed);
        if (!p.ok()) return p.error();
        probe_phases.push_back(phases_json(p->names, p->phase_ms));
        return p->ms;
    };
    sim::SoftBody after_10;  // the body after the 10th cut, probed again beside the last
    std::vector<double> probes;
    std::vector<double> ms(count), crossed(count);
    const core::Stopwatch total;
    for (uint32_t k = 0; k < count; ++k) {
        if (k == 0 || k == 10) {
            auto p = probe();
            if (!p.ok()) return p.error();
            probes.push_back(p.value());
            if (k == 10) after_10 = b;
        }
        const uint32_t at = south[size_t(std::abs(u(rng)) * float(south.size() - 1))];
        Vec3f n(u(rng), u(rng), u(rng));
        if (n.norm() < 0.1f) n = Vec3f::UnitY();
        const float r = edge * (1.5f + 2.0f * std::abs(u(rng)));
        auto change = topology::cut(b, topology::local_cut_on(b, at, n.normalized(), r), options);
        if (!change.ok()) return change.error();
        ms[k] = change->ms, crossed[k] = double(change->crossed_triangles);
        solver.step(b, 1.0f / 60.0f, s, {}, {});
    }
    auto p = probe();
    if (!p.ok()) return p.error();
    probes.push_back(p.value());
    nlohmann::json alternated;
    if (count > 10) {
        auto a = probe_alternated(prober, after_10, b);
        if (!a.ok()) return a.error();
        alternated = std::move(a).value();
    }
    auto window = [&](const std::vector<double>& v, size_t first) {
        std::vector<double> w(v.begin() + long(first), v.begin() + long(std::min(v.size(), first + 20)));
        return core::median(w);
    };
    const size_t last = count > 20 ? count - 20 : 0;
    return nlohmann::json{{"mesh", spec},
                          {"cuts", count},
                          {"particles_before", particles_before},
                          {"particles_after", b.particle_count()},
                          {"pieces_after", b.pieces},
                          {"cap_loops_after", std::accumulate(b.volumes.begin(), b.volumes.end(), size_t(0),
                                                              [](size_t n, const sim::VolumeConstraint& v) { return n + v.cap_loops.size(); })},
                          {"seconds", total.elapsed_ms() / 1000.0},
                          {"probe_ms_before", probes[0]},
                          {"probe_ms_after_10", probes.size() > 2 ? probes[1] : probes[0]},
                          {"probe_ms_after_last", probes.back()},
                          {"first_median_ms", window(ms, 0)},
                          {"last_median_ms", window(ms, last)},
                          {"first_median_crossed", window(crossed, 0)},
                          {"last_median_crossed", window(crossed, last)},
                          {"probe_phases_ms", probe_phases},
                          {"probe_alternated", alternated},
                          {"ring_compactions", b.rings.ring.compactions()},
                          {"distance_regroupings", b.distance_groups.regroupings},
                          {"distance_colours_added", b.distance_groups.colours_added}};
}

Outcome report_sequence(const std::string& spec, uint32_t count, const topology::CutOptions& options) {
    auto m = measure_sequence(spec, count, options);
    if (!m.ok()) return m.error();
    const nlohmann::json& j = m.value();
    Report report("cut");
    report.json()["sequence"] = j;
    report.line(format("%s: %u random scalpel cuts on one body, a frame between cuts (%.1f s)", spec.c_str(), count,
                       j["seconds"].get<double>()));
    report.line(format("  particles %zu -> %zu, pieces %zu, cap loops %zu; ring compactions %zu, colour regroupings %zu, colours added %zu",
                       j["particles_before"].get<size_t>(), j["particles_after"].get<size_t>(), j["pieces_after"].get<size_t>(),
                       j["cap_loops_after"].get<size_t>(), j["ring_compactions"].get<size_t>(),
                       j["distance_regroupings"].get<size_t>(), j["distance_colours_added"].get<size_t>()));
    // The probe's total and each phase: before the first cut, after the 10th, after the last.
    const nlohmann::json& phases = j["probe_phases_ms"];
    const nlohmann::json& after_10 = phases[phases.size() > 2 ? 1 : 0];
    Table probe({{"phase", 0, true, ""}, {"before", 3}, {"after_10", 3, true, "after 10"}, {"after_last", 3, true, format("after %u", count)}});
    probe.add({"probe cut (whole)", j["probe_ms_before"], j["probe_ms_after_10"], j["probe_ms_after_last"]});
    for (const auto& [name, before] : phases.front().items())
        probe.add({"  " + name, before, after_10.value(name, 0.0), phases.back().value(name, 0.0)});
    report.table("  probe cut (the same slit at the pole, median of 7 copies), ms:", probe, 4);
    if (const nlohmann::json& a = j["probe_alternated"]; a.is_object()) {
        Table alt({{"phase", 0, true, ""}, {"after_10", 3, true, "after 10"}, {"after_last", 3, true, format("after %u", count)}});
        alt.add({"probe cut (whole)", a["after_10_ms"], a["after_last_ms"]});
        for (const auto& [name, ms] : a["phases_after_10_ms"].items()) alt.add({"  " + name, ms, a["phases_after_last_ms"].value(name, 0.0)});
        report.table(format("  the same probe on both bodies again, alternated %d times (medians, ms; ratio %.2f):", a["rounds"].get<int>(),
                            a["ratio"].get<double>()),
                     alt, 4);
    }
    report.line(format("  the random cuts: 1-20 %.3f ms (median, %.0f crossed), last 20 %.3f ms (%.0f crossed)",
                       j["first_median_ms"].get<double>(), j["first_median_crossed"].get<double>(), j["last_median_ms"].get<double>(),
                       j["last_median_crossed"].get<double>()));
    return report;
}

// --levels A-B: the per-crossed-triangle cost of each icosphere level, and its ratio to the first.
Outcome report_levels(const std::string& range, uint32_t cuts, uint32_t frames, const topology::CutOptions& options) {
    unsigned lo = 0, hi = 0;
    char dash = 0;
    if (std::sscanf(range.c_str(), "%u%c%u", &lo, &dash, &hi) != 3 || dash != '-' || lo > hi || hi > 8)
        return Outcome::usage("--levels must be A-B with 0 <= A <= B <= 8 (icosphere levels), not '" + range + "'");
    nlohmann::json levels = nlohmann::json::array();
    for (unsigned level = lo; level <= hi; ++level) {
        auto m = measure_cuts("icosphere:" + std::to_string(level), cuts, frames, options);
        if (!m.ok()) return m.error();
        levels.push_back(std::move(m).value());
    }
    const double first = levels.front()["us_per_crossed_triangle"].get<double>();
    Table table({{"mesh", 0, true, ""}, {"particles_before", 0, true, "particles"}, {"crossed_triangles", 0, true, "crossed"}, {"median_cut_ms", 3, true, "cut ms"}, {"us_per_crossed_triangle", 2, true, "us/crossed"}, {"ratio_to_first", 2, true, "ratio"}});
    for (auto& l : levels) {
        l["ratio_to_first"] = first > 0.0 ? l["us_per_crossed_triangle"].get<double>() / first : 0.0;
        table.add({l["mesh"], l["particles_before"], l["crossed_triangles"], l["median_cut_ms"], l["us_per_crossed_triangle"],
                   l["ratio_to_first"]});
    }
    Report report("cut");
    report.json().update({{"cuts", cuts}, {"levels", levels}});
    report.table(format("cost per crossed triangle by icosphere level (%u cuts each through the centre, medians):", cuts), table);
    return report;
}

const CommandSpec& command_spec() {
    static const CommandSpec command{
        "bench cut", "",
        "The cost of one line cut through the middle of a body at rest (paper section 5.7): N cuts,\n"
        "each on a copy of the body (in the same storage) along a plane through its centre at a\n"
        "different angle, median milliseconds of the cut (and of rebuilding the solver's derived data\n"
        "inside it), the crossed region, and Stage A ms per frame (paper solver defaults, median of F\n"
        "frames) before and after the first cut, and of one frame timed before each cut; then the\n"
        "cost per crossed triangle and the median ms of each step of the cut, in the order run. The\n"
        "body is stepped once by the solver first, as a body in a scene always has been (a cut takes\n"
        "a piece's volume from the solver's last measure), and each copy gets the spare capacity a\n"
        "live body keeps from its earlier edits (sim::reserve_headroom), outside the timing.\n",
        {text("mesh", "SPEC", "", "the body: a model from ../shared/models, an OBJ, or a procedural spec")
             .default_from("teapot.obj; icosphere:4 with --sequence"),
         whole("cuts", "N", 20, 1, 10000, "cuts, each on a copy of the uncut body"),
         named<topology::VolumePolicy>("policy", topology::k_volume_policy_names, topology::VolumePolicy::cap,
                                       "volume policy of the cut"),
         whole("frames", "F", 30, 1, 10000, "Stage A frames timed before and after"),
         text("levels", "A-B", "", "instead of --mesh: icosphere levels A to B, a table of the cost per crossed\n"
                                   "triangle at each and its ratio to level A's (how the cut scales)")
             .default_from("off"),
         whole("sequence", "N", 1000, 1, 100000,
               "instead: N random scalpel cuts (topology::local_cut_on) on the southern part of one\n"
               "body, a frame between cuts; the same probe slit at the north pole timed on copies\n"
               "(assigned into storage kept between them, as a live body keeps its arrays) before,\n"
               "after 10 and after N (does a cut cost more once the body has been cut N times?), then\n"
               "on the bodies after 10 and after N again, alternated 5 times: the figure to trust on a\n"
               "machine whose speed drifts over minutes")
             .default_from("off"),
         json_option()}};
    return command;
}

Outcome measure(const Options& opt) {
    const uint32_t cuts = opt.whole("cuts"), frames = opt.whole("frames");
    topology::CutOptions options;
    options.volume = opt.named<topology::VolumePolicy>("policy", topology::k_volume_policy_names);
    const std::string& policy = opt.text("policy");

    const std::string& mesh = opt.text("mesh");
    if (opt.given("sequence")) return report_sequence(mesh.empty() ? "icosphere:4" : mesh, opt.whole("sequence"), options);
    if (opt.given("levels")) return report_levels(opt.text("levels"), cuts, frames, options);
    const std::string spec = mesh.empty() ? "teapot.obj" : mesh;
    auto measured = measure_cuts(spec, cuts, frames, options);
    if (!measured.ok()) return measured.error();
    const nlohmann::json& j = measured.value();
    Report report("cut");
    report.json().update(j);
    report.json().update({{"policy", policy}, {"cuts", cuts}});
    report.line(format("%s: %zu particles, %zu triangles; %u cuts through the centre (%s)", spec.c_str(),
                       j["particles_before"].get<size_t>(), j["triangles_before"].get<size_t>(), cuts, policy.c_str()));
    std::vector<Figure> figures = {{"crossed triangles", j["crossed_triangles"].get<double>(), "", 0},
                                   {"particles after", j["particles_after"].get<double>(), "", 0},
                                   {"particles searched for the pieces", j["particles_searched"].get<double>(), "", 0},
                                   {"pieces swept whole", j["pieces_swept_whole"].get<double>(), "", 0},
                                   {"cut (median)", j["median_cut_ms"].get<double>(), "ms"},
                                   {"of which derived solver data", j["median_rebuild_ms"].get<double>(), "ms"},
                                   {"per crossed triangle", j["us_per_crossed_triangle"].get<double>(), "us", 2}};
    for (const auto& p : j["phases"]) figures.push_back({"  " + p["name"].get<std::string>(), p["median_ms"].get<double>(), "ms"});
    figures.push_back({"Stage A before the cut", j["stage_a_ms_before"].get<double>(), "ms/frame"});
    figures.push_back({"Stage A after the cut", j["stage_a_ms_after"].get<double>(), "ms/frame"});
    figures.push_back({"Stage A between the cuts", j["stage_a_ms_between_cuts"].get<double>(), "ms/frame (caches cold)"});
    report.figures("", figures);
    return report;
}

} // namespace

const BenchSuite k_bench_cut{"cut", "one line cut: its milliseconds, the crossed region, Stage A before and after", command_spec,
                             measure};

} // namespace pbdsplat::cli
