#pragma once
// One runner for every `pbdsplat bench <suite>`: it parses the suite's option table, runs the
// measurement, and shows its Report (text or --json) and writes its files into --out-dir. A
// suite only measures and fills the report.
#include <string>
#include <variant>
#include <vector>

#include "core/result.h"
#include "pbdsplat/options.h"
#include "pbdsplat/report.h"

namespace pbdsplat::cli {

// How a measurement ends: its report, or what stopped it (exit 1; a usage error exits 2).
class Outcome {
public:
    Outcome(Report report) : v_(std::move(report)) {}
    Outcome(core::Error error) : v_(std::move(error)) {}
    // A value the option table could not check (a list item out of range, a combination).
    static Outcome usage(std::string message) {
        Outcome o(core::make_error(std::move(message)));
        o.usage_ = true;
        return o;
    }
    bool ok() const { return v_.index() == 0; }
    bool is_usage() const { return usage_; }
    Report& report() { return std::get<0>(v_); }
    const core::Error& error() const { return std::get<1>(v_); }

private:
    std::variant<Report, core::Error> v_;
    bool usage_ = false;
};

struct BenchSuite {
    const char* name;     // after `pbdsplat bench`
    const char* summary;  // one line for `pbdsplat bench --help`
    const CommandSpec& (*spec)();
    Outcome (*measure)(const Options&);
};

// Parses, measures, writes the files, prints; returns the exit code.
int run_bench(const BenchSuite& suite, const std::vector<std::string>& argv);

} // namespace pbdsplat::cli
