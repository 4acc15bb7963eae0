#pragma once
// One function per `pbdsplat <command>`; each returns the process exit code.
#include <string>
#include <vector>

namespace pbdsplat::cli {

int cmd_info(const std::vector<std::string>& args);
int cmd_run(const std::vector<std::string>& argv);
int cmd_render(const std::vector<std::string>& args);
int cmd_bench(const std::vector<std::string>& args);
int cmd_graph(const std::vector<std::string>& args);
int cmd_validate_scene(const std::vector<std::string>& args);
int cmd_check(const std::vector<std::string>& args);
int cmd_export_ply(const std::vector<std::string>& args);

// Prints "pbdsplat <command>: <message>" to stderr and returns 1.
int fail(const std::string& command, const std::string& message);
// Same, for a malformed command line: returns 2.
int usage_error(const std::string& command, const std::string& message);

} // namespace pbdsplat::cli
