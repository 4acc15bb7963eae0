#include "core/timer.h"
#include "graph/frame_graph.h"
#include "pbdsplat/bench_suites.h"

namespace pbdsplat::cli {
namespace {

const CommandSpec& command_spec() {
    static const CommandSpec command{
        "bench graph", "",
        "The frame graph's own cost: a graph of N passes of which all but one are culled (they need\n"
        "a resource that is absent), compiled once, executed F times; prints the median and the\n"
        "mean microseconds of one execute(), and the cost of one compile().\n",
        {whole("passes", "N", 30, 1, 100000, "passes in the graph (30 is like the default scene)"),
         whole("frames", "F", 100000, 1, 100000000, "executions"), json_option()}};
    return command;
}

Outcome measure(const Options& opt) {
    const uint32_t passes = opt.whole("passes"), frames = opt.whole("frames");
    graph::FrameGraph g;
    int state = 0, counter = 0;
    auto body = g.import("body", &state, true);
    auto missing = g.import("absent", static_cast<int*>(nullptr));
    g.add_pass("kept", graph::PassKind::cpu, [&](graph::PassBuilder& b) {
        body = b.write(body);
        return [&counter](const graph::PassResources&, graph::ExecuteContext&) { ++counter; };
    });
    for (uint32_t i = 1; i < passes; ++i)
        g.add_pass("culled." + std::to_string(i), graph::PassKind::cpu, [&](graph::PassBuilder& b) {
            b.read(missing);
            body = b.write(body);
            return [&counter](const graph::PassResources&, graph::ExecuteContext&) { ++counter; };
        });
    const core::Stopwatch compile_clock;
    PBDSPLAT_TRY(g.compile());
    const double compile_us = compile_clock.elapsed_ms() * 1000.0;

    // Timed in batches of 100, since one execute is below the clock's useful resolution.
    std::vector<double> us;
    graph::ExecuteContext ctx;
    const uint32_t batch = 100;
    for (uint32_t f = 0; f < frames; f += batch) {
        const core::Stopwatch clock;
        for (uint32_t k = 0; k < batch; ++k) g.execute(ctx);
        us.push_back(clock.elapsed_ms() * 1000.0 / batch);
    }
    const double mean = core::mean(us);
    if (counter != int(us.size() * batch)) return core::make_error("a culled pass ran");
    Report report("graph");
    report.json().update({{"passes", passes}, {"kept", 1}, {"median_us", core::median(us)}, {"mean_us", mean}, {"compile_us", compile_us}});
    report.figures(format("%u passes, 1 kept:", passes),
                   {{"execute, median per frame", core::median(us), "us"}, {"execute, mean per frame", mean, "us"},
                    {"compile, once", compile_us, "us", 1}});
    return report;
}

} // namespace

const BenchSuite k_bench_graph{"graph", "the frame graph's own overhead per frame", command_spec, measure};

} // namespace pbdsplat::cli
