#include <cstdio>

#include <nlohmann/json.hpp>

#include "pbdsplat/commands.h"
#include "pbdsplat/gpu_options.h"
#include "scene/model_scene.h"

namespace pbdsplat::cli {
namespace {

int model_info(const std::string& path, bool json) {
    auto kind = scene::input_kind(path);
    if (!kind.ok()) return fail("info", kind.error().to_string());
    if (kind.value() != scene::InputKind::model)
        return fail("info", path + ": is " + (kind.value() == scene::InputKind::scene ? "a scene (pbdsplat validate-scene checks it)"
                                                                                     : "a file of 3D Gaussians (pbdsplat render shows it)") +
                                ", not a model");
    auto s = scene::summarize_model(path);
    if (!s.ok()) return fail("info", s.error().to_string());
    const scene::ModelSummary& m = s.value();
    if (json) {
        const nlohmann::json j = {{"file", path}, {"format", m.format}, {"up", m.up}, {"vertices", m.vertices}, {"triangles", m.triangles},
                                  {"materials", m.materials}, {"textures", m.textures}, {"vertex_colors", m.vertex_colors},
                                  {"texture_coordinates", m.texture_coordinates}, {"repair", m.repair},
                                  {"refined_levels", m.refined_levels}, {"warnings", m.warnings}};
        std::printf("%s\n", j.dump().c_str());
        return 0;
    }
    std::printf("file             %s\n", path.c_str());
    std::printf("format           %s\n", m.format.c_str());
    std::printf("up               %s\n", m.up.c_str());
    std::printf("as read          %zu vertices, %zu triangles\n", m.vertices, m.triangles);
    std::printf("materials        %zu\n", m.materials);
    for (const std::string& t : m.textures) std::printf("texture          %s\n", t.c_str());
    std::printf("colours          %s%s\n", m.vertex_colors ? "vertex colours" : "no vertex colours",
                m.texture_coordinates ? ", texture coordinates" : "");
    std::printf("repaired         %s\n", m.repair.c_str());
    if (m.refined_levels) std::printf("refined          subdivided %u times (a small model, or its low-poly parts)\n", m.refined_levels);
    for (const std::string& w : m.warnings) std::printf("warning          %s\n", w.c_str());
    return 0;
}

} // namespace

int cmd_info(const std::vector<std::string>& argv) {
    static const CommandSpec command{
        "info", "[MODEL]",
        "Prints the Vulkan device pbdsplat would use, its driver and API version, and the features\n"
        "the renderer branches on: geometry shader, mesh shader, timestamp queries, subgroup size,\n"
        "and whether uploads are written in place (unified memory) or staged.\n"
        "With a model file, prints what pbdsplat reads from it instead (no device needed): its\n"
        "format, size, materials, textures, colours, what repair changed, and any warning.\n",
        with_gpu({json_option()})};
    const Parsed parsed = parse_command(command, argv);
    if (!parsed.options) return parsed.exit_code;
    const Options& opt = *parsed.options;
    if (opt.operands().size() > 1) return usage_error("info", "takes at most one model file");
    if (opt.operands().size() == 1) return model_info(opt.operands()[0], opt.flag("json"));

    auto ctx = open_context(opt);
    if (!ctx.ok()) return fail("info", ctx.error().to_string());
    const gpu::DeviceCaps& c = ctx.value()->caps();
    if (opt.flag("json")) {
        const nlohmann::json j = {{"device", c.name},
                                  {"device_type", c.type},
                                  {"driver", c.driver},
                                  {"api_version", gpu::api_version_string(c.api_version)},
                                  {"geometry_shader", c.geometry_shader},
                                  {"mesh_shader", c.mesh_shader},
                                  {"timestamps", c.timestamps},
                                  {"pipeline_statistics", c.pipeline_statistics},
                                  {"subgroup_size", c.subgroup_size},
                                  {"unified_memory", c.unified_memory}};
        std::printf("%s\n", j.dump().c_str());
    } else {
        std::printf("device           %s (%s)\n", c.name.c_str(), c.type.c_str());
        std::printf("driver           %s\n", c.driver.c_str());
        std::printf("api version      %s\n", gpu::api_version_string(c.api_version).c_str());
        std::printf("geometry shader  %s\n", c.geometry_shader ? "yes" : "no");
        std::printf("mesh shader      %s\n", c.mesh_shader ? "yes (VK_EXT_mesh_shader)" : "no (VK_EXT_mesh_shader missing)");
        std::printf("timestamps       %s\n", c.timestamps ? "yes" : "no");
        std::printf("pipeline stats   %s\n", c.pipeline_statistics ? "yes (splat work counted)" : "no (splat work not counted)");
        std::printf("subgroup size    %u\n", c.subgroup_size);
        std::printf("uploads          %s\n", c.unified_memory ? "direct (unified memory: written in place)"
                                                               : "staged (copied from a host-visible ring)");
    }
    auto v = check_validation(*ctx.value());
    return v.ok() ? 0 : fail("info", v.error().to_string());
}

} // namespace pbdsplat::cli
