#pragma once
// The bench suites, each defined in its own bench_<suite>.cpp; cmd_bench.cpp lists them.
#include "pbdsplat/bench_runner.h"

namespace pbdsplat::cli {

extern const BenchSuite k_bench_sim, k_bench_sim_error, k_bench_graph, k_bench_scene, k_bench_surface, k_bench_cut,
    k_bench_render, k_bench_render_error, k_bench_temporal, k_bench_coverage, k_bench_splat, k_bench_load;

} // namespace pbdsplat::cli
