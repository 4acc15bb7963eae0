#include <cstdio>
#include <fstream>

#include <nlohmann/json.hpp>

#include "pbdsplat/commands.h"
#include "pbdsplat/gpu_options.h"
#include "pbdsplat/scene_arg.h"
#include "scene/scene_runtime.h"

namespace pbdsplat::cli {

int cmd_graph(const std::vector<std::string>& argv) {
    static const CommandSpec command{
        "graph", "[SCENE.toml]",
        "Compiles the frame graph of a scene (default: the built-in one) and prints its passes in\n"
        "execution order, each with the timing group its time counts towards (bench scene's rows), and\n"
        "the culled ones marked with the reason: a resource the scene does not have (\"needs volume\n"
        "constraints\") or an output nobody reads (\"unused\").\n",
        with_gpu({flag("present", "as for a window: no readback of the image"),
                  text("dot", "FILE", "", "also write the graph as Graphviz dot").default_from("none"),
                  json_option("print {\"passes\": [{\"name\", \"kind\", \"group\", \"culled\", \"reason\", \"barriers\"}]}")})};
    const Parsed parsed = parse_command(command, argv);
    if (!parsed.options) return parsed.exit_code;
    const Options& opt = *parsed.options;
    auto scene = load_scene_arg(opt.operands());
    if (!scene.ok()) return fail("graph", scene.error().to_string());
    auto ctx = open_context(opt);
    if (!ctx.ok()) return fail("graph", ctx.error().to_string());
    scene::RuntimeOptions options;
    options.gpu = ctx.value().get();
    options.readback = !opt.flag("present");
    auto runtime = scene::SceneRuntime::create(scene.value(), options);
    if (!runtime.ok()) return fail("graph", runtime.error().to_string());
    const auto passes = runtime.value()->graph().describe();

    if (const std::string& dot = opt.text("dot"); !dot.empty()) {
        std::ofstream out(dot);
        if (!out) return fail("graph", dot + ": cannot write");
        out << runtime.value()->graph().to_dot();
    }
    if (opt.flag("json")) {
        nlohmann::json j = {{"scene", scene->name}, {"passes", nlohmann::json::array()}};
        for (const auto& p : passes)
            j["passes"].push_back({{"name", p.name},
                                   {"kind", p.kind == graph::PassKind::gpu ? "gpu" : "cpu"},
                                   {"group", scene::group_key(p.tag)},
                                   {"culled", p.culled},
                                   {"reason", p.reason},
                                   {"barriers", p.barriers}});
        std::printf("%s\n", j.dump().c_str());
    } else {
        size_t kept = 0;
        for (const auto& p : passes) {
            kept += p.culled ? 0 : 1;
            std::printf("  %-18s %s  %-21s  %s%s\n", p.name.c_str(), p.kind == graph::PassKind::gpu ? "gpu" : "cpu", scene::group_key(p.tag),
                        p.culled ? "culled: " : "", p.culled ? p.reason.c_str()
                                                             : (p.barriers ? (std::to_string(p.barriers) + " barrier(s)").c_str() : ""));
        }
        std::printf("scene %s: %zu of %zu passes run\n", scene->name.c_str(), kept, passes.size());
    }
    if (auto v = check_validation(*ctx.value()); !v.ok()) return fail("graph", v.error().to_string());
    return 0;
}

} // namespace pbdsplat::cli
