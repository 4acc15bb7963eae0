#include "pbdsplat/bench_runner.h"

#include <cstdio>

#include "pbdsplat/commands.h"

namespace pbdsplat::cli {

int run_bench(const BenchSuite& suite, const std::vector<std::string>& argv) {
    const CommandSpec& spec = suite.spec();
    const Parsed parsed = parse_command(spec, argv);
    if (!parsed.options) return parsed.exit_code;
    const Options& opt = *parsed.options;
    Outcome outcome = suite.measure(opt);
    if (!outcome.ok())
        return outcome.is_usage() ? usage_error(spec.name, outcome.error().message) : fail(spec.name, outcome.error().to_string());
    Report& report = outcome.report();
    if (report.has_files()) {
        std::vector<std::string> written;
        if (auto s = report.write_files(opt.text("out-dir"), written); !s.ok()) return fail(spec.name, s.error().to_string());
        report.json()["files"] = written;
        std::string list;
        for (const std::string& w : written) list += (list.empty() ? "" : ", ") + w;
        report.line("wrote " + list);
    }
    if (opt.flag("json"))
        std::printf("%s\n", report.json().dump().c_str());
    else
        std::fputs(report.text().c_str(), stdout);
    return 0;
}

} // namespace pbdsplat::cli
