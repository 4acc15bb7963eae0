#pragma once
// A command's options, declared once: the table gives the parser its names, kinds, defaults and
// ranges, and `--help` its text, so the two cannot disagree. Every value is checked while
// parsing; a command reads only values already known to be valid.
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "core/names.h"

namespace pbdsplat::cli {

enum class OptionKind { flag, whole, real, text, choice };

struct Option {
    std::string name;
    OptionKind kind = OptionKind::flag;
    std::string value_name;  // as shown in help: N, PATH, ...
    std::string help;
    double fallback = 0.0, min = 0.0, max = 0.0;  // whole and real
    std::string text_fallback;                    // text and choice
    std::vector<std::string> choices;
    std::string shown_default;  // help's "default ..." when the value comes from elsewhere (the scene)

    // The default help shows, when the fallback is not what a user gets.
    Option&& default_from(std::string where) && {
        shown_default = std::move(where);
        return std::move(*this);
    }
};

Option flag(std::string name, std::string help);
Option whole(std::string name, std::string value_name, uint32_t fallback, uint32_t min, uint32_t max, std::string help);
Option real(std::string name, std::string value_name, float fallback, float min, float max, std::string help);
Option text(std::string name, std::string value_name, std::string fallback, std::string help);
Option choice(std::string name, std::vector<std::string> choices, std::string fallback, std::string help);
// A choice among an enum's names, from its one name table.
template <class E>
Option named(std::string name, std::span<const core::EnumName<E>> table, E fallback, std::string help) {
    return choice(std::move(name), core::names_of(table), core::name_of(table, fallback), std::move(help));
}

// The two options of every command that opens a Vulkan device.
std::vector<Option> gpu_options();
// A command's own options followed by those two.
std::vector<Option> with_gpu(std::vector<Option> own);
// --json, with what the object holds.
Option json_option(std::string what = "one JSON object on stdout");

struct CommandSpec {
    std::string name;      // as typed after `pbdsplat`: "bench cut"
    std::string operands;  // usage's operands: "[SCENE.toml]"
    std::string about;     // paragraphs between usage and options
    std::vector<Option> options;
};

// The parsed values. Reading an undeclared name, or one of another kind, is a bug in the
// command and aborts with the name (declare it in the command's table).
class Options {
public:
    bool flag(const std::string& name) const;
    // Was the option given on the command line (for values whose default comes from elsewhere)?
    bool given(const std::string& name) const;
    uint32_t whole(const std::string& name) const;
    float real(const std::string& name) const;
    // A text or choice value (choices already checked).
    const std::string& text(const std::string& name) const;
    // A `named` option's enum.
    template <class E>
    E named(const std::string& name, std::span<const core::EnumName<E>> table) const {
        return *core::from_name(table, text(name));
    }
    const std::vector<std::string>& operands() const { return operands_; }

private:
    friend struct OptionsParser;
    const Option& declared(const std::string& name, OptionKind kind) const;
    const std::vector<Option>* table_ = nullptr;
    std::set<std::string> given_;
    std::map<std::string, double> numbers_;
    std::map<std::string, std::string> texts_;
    std::vector<std::string> operands_;
};

// The options, or the exit code of a command that ends here: 0 after --help (printed on
// stdout), 2 after a malformed command line (the error printed on stderr).
struct Parsed {
    std::optional<Options> options;
    int exit_code = 0;
};
Parsed parse_command(const CommandSpec& spec, const std::vector<std::string>& argv);

// The non-empty items of a comma-separated list ("a,b,,c" -> a, b, c).
std::vector<std::string> split_list(const std::string& list);

// The help text the table gives: usage, about, one line per option with default and range.
std::string help_text(const CommandSpec& spec);

} // namespace pbdsplat::cli
