#include <algorithm>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "asset/mesh_spec.h"
#include "asset/model_file.h"
#include "core/timer.h"
#include "pbdsplat/bench_suites.h"
#include "scene/model_scene.h"
#include "scene/scene_runtime.h"

namespace pbdsplat::cli {
namespace {

const CommandSpec& command_spec() {
    static const CommandSpec command{
        "bench load", "MODEL...",
        "How long a model file takes from disk to a body ready to draw, each the median of --repeat\n"
        "runs from the file: `read` (parsed, materials and textures decoded), `repaired` (read, then\n"
        "welded, oriented and fitted; a small file subdivided), and `ready` (all that `pbdsplat run\n"
        "MODEL` does before its first frame but the device: its scene, the decimated simulation\n"
        "mesh, the boundary particles sampled, embedded and painted).\n",
        {whole("repeat", "N", 3, 1, 100, "runs per file (the median is shown)"), out_dir_option(), json_option()}};
    return command;
}

template <class F>
core::Result<double> median_ms(uint32_t repeat, const F& run) {
    std::vector<double> ms;
    for (uint32_t i = 0; i < repeat; ++i) {
        asset::forget_loads();  // each run from the file, as a first run is
        const core::Stopwatch clock;
        PBDSPLAT_TRY(run());
        ms.push_back(clock.elapsed_ms());
    }
    std::sort(ms.begin(), ms.end());
    return ms[ms.size() / 2];
}

Outcome measure(const Options& opt) {
    if (opt.operands().empty()) return Outcome::usage("name one or more model files");
    const uint32_t repeat = opt.whole("repeat");
    Table table({{"file", 0, true, ""}, {"format", 0}, {"triangles", 0}, {"textures", 0}, {"samples", 0},
                 {"read_ms", 1}, {"repaired_ms", 1}, {"ready_ms", 1}});
    nlohmann::json files = nlohmann::json::array();
    for (const std::string& path : opt.operands()) {
        auto kind = asset::sniff_file(path);
        if (!kind.ok()) return kind.error();
        size_t triangles = 0, textures = 0, samples = 0;
        auto read = median_ms(repeat, [&]() -> core::Status {
            auto a = asset::load_model_file(path);
            if (!a.ok()) return a.error();
            triangles = a->mesh.triangle_count();
            textures = a->look ? a->look->textures.size() : 0;
            return core::Status::success();
        });
        if (!read.ok()) return read.error();
        auto repair = median_ms(repeat, [&]() -> core::Status {
            auto m = asset::load_model(path);
            return m.ok() ? core::Status::success() : core::Status(m.error());
        });
        if (!repair.ok()) return repair.error();
        auto ready = median_ms(repeat, [&]() -> core::Status {
            auto scene = scene::scene_for_model(path);
            if (!scene.ok()) return scene.error();
            auto rt = scene::SceneRuntime::create(scene.value(), {});
            if (!rt.ok()) return rt.error();
            samples = rt.value()->boundary_particles().size();
            return core::Status::success();
        });
        if (!ready.ok()) return ready.error();
        const std::string name = std::filesystem::path(path).filename().string();
        table.add({name, asset::file_kind_name(kind.value()), triangles, textures, samples, read.value(), repair.value(), ready.value()});
    }
    Report report("load");
    report.json().update({{"repeat", repeat}});
    report.table(format("model files, median of %u runs (ms):", repeat), table);
    report.csv("load.csv", table);
    return report;
}

} // namespace

const BenchSuite k_bench_load{"load", "a model file from disk to a body ready to draw: read, repair, sample (ms)", command_spec, measure};

} // namespace pbdsplat::cli
