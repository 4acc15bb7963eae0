#include <cstdio>

#include <nlohmann/json.hpp>

#include "pbdsplat/commands.h"
#include "pbdsplat/gpu_options.h"

namespace pbdsplat::cli {

int cmd_info(const std::vector<std::string>& argv) {
    static const CommandSpec command{
        "info", "",
        "Prints the Vulkan device pbdsplat would use, its driver and API version, and the features\n"
        "the renderer branches on: geometry shader, mesh shader, timestamp queries, subgroup size,\n"
        "and whether uploads are written in place (unified memory) or staged.\n",
        with_gpu({json_option()})};
    const Parsed parsed = parse_command(command, argv);
    if (!parsed.options) return parsed.exit_code;
    const Options& opt = *parsed.options;
    if (!opt.operands().empty()) return usage_error("info", "takes no positional arguments");

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
        std::printf("subgroup size    %u\n", c.subgroup_size);
        std::printf("uploads          %s\n", c.unified_memory ? "direct (unified memory: written in place)"
                                                               : "staged (copied from a host-visible ring)");
    }
    auto v = check_validation(*ctx.value());
    return v.ok() ? 0 : fail("info", v.error().to_string());
}

} // namespace pbdsplat::cli
