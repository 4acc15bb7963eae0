#include "pbdsplat/options.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "core/result.h"
#include "core/spelling.h"

namespace pbdsplat::cli {

Option flag(std::string name, std::string help) {
    Option o;
    o.name = std::move(name);
    o.help = std::move(help);
    return o;
}

namespace {

Option numeric(OptionKind kind, std::string name, std::string value_name, double fallback, double min, double max, std::string help) {
    Option o = flag(std::move(name), std::move(help));
    o.kind = kind;
    o.value_name = std::move(value_name);
    o.fallback = fallback, o.min = min, o.max = max;
    return o;
}

} // namespace

Option whole(std::string name, std::string value_name, uint32_t fallback, uint32_t min, uint32_t max, std::string help) {
    return numeric(OptionKind::whole, std::move(name), std::move(value_name), fallback, min, max, std::move(help));
}

Option real(std::string name, std::string value_name, float fallback, float min, float max, std::string help) {
    return numeric(OptionKind::real, std::move(name), std::move(value_name), fallback, min, max, std::move(help));
}

Option text(std::string name, std::string value_name, std::string fallback, std::string help) {
    Option o = flag(std::move(name), std::move(help));
    o.kind = OptionKind::text;
    o.value_name = std::move(value_name);
    o.text_fallback = std::move(fallback);
    return o;
}

Option choice(std::string name, std::vector<std::string> choices, std::string fallback, std::string help) {
    Option o = flag(std::move(name), std::move(help));
    o.kind = OptionKind::choice;
    for (const auto& c : choices) o.value_name += (o.value_name.empty() ? "" : "|") + c;
    o.choices = std::move(choices);
    o.text_fallback = std::move(fallback);
    return o;
}

std::vector<Option> gpu_options() {
    return {flag("validation", "enable the Khronos validation layer; any message makes the command fail"),
            text("device", "NAME", "", "pick the Vulkan device whose name contains NAME")
                .default_from("$PBDSPLAT_DEVICE, else the first")};
}

std::vector<Option> with_gpu(std::vector<Option> own) {
    for (Option& o : gpu_options()) own.push_back(std::move(o));
    return own;
}

Option json_option(std::string what) { return flag("json", std::move(what)); }

namespace {

std::string number(double v) {
    char buf[32];
    if (v == std::floor(v) && std::abs(v) < 1e15) std::snprintf(buf, sizeof buf, "%.0f", v);
    else std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

const Option* find(const std::vector<Option>& table, const std::string& name) {
    for (const Option& o : table)
        if (o.name == name) return &o;
    return nullptr;
}

// "; did you mean --frames?" for a near spelling of one of the command's options, else "".
std::string option_hint(const std::vector<Option>& table, const std::string& name) {
    std::vector<std::string> names{"help"};
    for (const Option& o : table) names.push_back(o.name);
    const auto near = core::nearest_spelling(name, names);
    return near ? "; did you mean --" + *near + "?" : std::string();
}

bool is_choice(const Option& o, const std::string& v) {
    for (const auto& c : o.choices)
        if (c == v) return true;
    return false;
}

// A value checked against its option's kind and range.
core::Status accept(const Option& o, const std::string& v, std::map<std::string, double>& numbers,
                    std::map<std::string, std::string>& texts) {
    const std::string range = " between " + number(o.min) + " and " + number(o.max) + ", got " + v;
    if (o.kind == OptionKind::whole) {
        uint64_t out = 0;
        const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), out);
        if (ec != std::errc() || end != v.data() + v.size())
            return core::make_error("--" + o.name + " expects a whole number, got '" + v + "'");
        if (double(out) < o.min || double(out) > o.max) return core::make_error("--" + o.name + " must be" + range);
        numbers[o.name] = double(out);
    } else if (o.kind == OptionKind::real) {
        float out = 0.0f;
        const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), out);
        if (ec != std::errc() || end != v.data() + v.size() || !std::isfinite(out))
            return core::make_error("--" + o.name + " expects a number, got '" + v + "'");
        if (double(out) < o.min || double(out) > o.max) return core::make_error("--" + o.name + " must be" + range);
        numbers[o.name] = double(out);
    } else {
        if (o.kind == OptionKind::choice && !is_choice(o, v))
        {
            std::string all;
            for (const auto& c : o.choices) all += (all.empty() ? "" : ", ") + c;
            const auto near = core::nearest_spelling(v, o.choices);
            return core::make_error("--" + o.name + " must be one of " + all + ", not '" + v + "'" +
                                    (near ? "; did you mean '" + *near + "'?" : std::string()));
        }
        texts[o.name] = v;
    }
    return core::Status::success();
}

} // namespace

struct OptionsParser {
    static core::Result<Options> parse(const CommandSpec& spec, const std::vector<std::string>& argv, bool& help) {
        Options out;
        out.table_ = &spec.options;
        for (const Option& o : spec.options) {
            if (o.kind == OptionKind::whole || o.kind == OptionKind::real) out.numbers_[o.name] = o.fallback;
            if (o.kind == OptionKind::text || o.kind == OptionKind::choice) out.texts_[o.name] = o.text_fallback;
        }
        for (size_t i = 0; i < argv.size(); ++i) {
            const std::string& arg = argv[i];
            if (arg == "--help" || arg == "-h") {
                help = true;
                return out;
            }
            if (arg.rfind("--", 0) != 0 || arg == "--") {
                out.operands_.push_back(arg);
                continue;
            }
            std::string name = arg.substr(2), value;
            const size_t eq = name.find('=');
            const bool inline_value = eq != std::string::npos;
            if (inline_value) value = name.substr(eq + 1), name = name.substr(0, eq);
            const Option* o = find(spec.options, name);
            if (!o) return core::make_error("unknown option --" + name + option_hint(spec.options, name) + " (see --help)");
            if (out.given_.count(name)) return core::make_error("--" + name + " given twice");
            out.given_.insert(name);
            if (o->kind == OptionKind::flag) {
                if (inline_value) return core::make_error("--" + name + " takes no value");
                continue;
            }
            if (!inline_value) {
                if (i + 1 >= argv.size()) return core::make_error("--" + name + " needs a value");
                value = argv[++i];
            }
            if (auto s = accept(*o, value, out.numbers_, out.texts_); !s.ok()) return s.error();
        }
        return out;
    }
};

Parsed parse_command(const CommandSpec& spec, const std::vector<std::string>& argv) {
    bool help = false;
    auto r = OptionsParser::parse(spec, argv, help);
    if (help) {
        std::fputs(help_text(spec).c_str(), stdout);
        return {std::nullopt, 0};
    }
    if (!r.ok()) {
        std::fprintf(stderr, "pbdsplat %s: %s\n", spec.name.c_str(), r.error().to_string().c_str());
        return {std::nullopt, 2};
    }
    return {std::move(r.value()), 0};
}

namespace {

std::string default_of(const Option& o) {
    if (!o.shown_default.empty()) return o.shown_default;
    switch (o.kind) {
    case OptionKind::flag: return "";
    case OptionKind::whole:
    case OptionKind::real: return number(o.fallback);
    case OptionKind::text:
    case OptionKind::choice: return o.text_fallback.empty() ? "" : o.text_fallback;
    }
    return "";
}

// One option's help: the text, then its default and range in brackets.
std::string option_line(const Option& o) {
    std::string left = "  --" + o.name + (o.value_name.empty() ? "" : " " + o.value_name);
    constexpr size_t column = 26;
    left += left.size() + 2 <= column ? std::string(column - left.size(), ' ') : "\n" + std::string(column, ' ');
    std::string notes;
    if (const std::string d = default_of(o); !d.empty()) notes = "default " + d;
    if (o.kind == OptionKind::whole || o.kind == OptionKind::real)
        notes += (notes.empty() ? "" : "; ") + number(o.min) + " to " + number(o.max);
    const std::string body = o.help + (notes.empty() ? "" : " (" + notes + ")");
    // Reflowed to end before column 100 (a newline in the help is a space), continuations
    // lined up under the first line.
    constexpr size_t width = 100 - column;
    std::string out, line;
    auto flush = [&] {
        out += (out.empty() ? "" : "\n" + std::string(column, ' ')) + line;
        line.clear();
    };
    size_t start = 0;
    while (start <= body.size()) {
        const size_t end = std::min(body.find_first_of(" \n", start), body.size());
        const std::string word = body.substr(start, end - start);
        if (!line.empty() && line.size() + 1 + word.size() > width) flush();
        line += (line.empty() ? "" : " ") + word;
        start = end + 1;
    }
    if (!line.empty()) flush();
    return left + out + "\n";
}

} // namespace

std::vector<std::string> split_list(const std::string& list) {
    std::vector<std::string> out;
    for (size_t start = 0; start <= list.size();) {
        const size_t end = std::min(list.find(',', start), list.size());
        if (end > start) out.push_back(list.substr(start, end - start));
        start = end + 1;
    }
    return out;
}

std::string help_text(const CommandSpec& spec) {
    std::string out = "usage: pbdsplat " + spec.name + (spec.operands.empty() ? "" : " " + spec.operands) +
                      (spec.options.empty() ? "" : " [options]") + "\n\n" + spec.about;
    if (!spec.about.empty() && spec.about.back() != '\n') out += "\n";
    out += "\noptions:\n";
    for (const Option& o : spec.options) out += option_line(o);
    out += "  --help                  this text\n";
    return out;
}

bool Options::flag(const std::string& name) const {
    declared(name, OptionKind::flag);
    return given_.count(name) > 0;
}

bool Options::given(const std::string& name) const {
    if (!table_ || !find(*table_, name)) declared(name, OptionKind::flag);
    return given_.count(name) > 0;
}

uint32_t Options::whole(const std::string& name) const {
    declared(name, OptionKind::whole);
    return uint32_t(numbers_.at(name));
}

float Options::real(const std::string& name) const {
    declared(name, OptionKind::real);
    return float(numbers_.at(name));
}

const std::string& Options::text(const std::string& name) const {
    const Option* o = table_ ? find(*table_, name) : nullptr;
    if (!o || (o->kind != OptionKind::text && o->kind != OptionKind::choice)) declared(name, OptionKind::text);
    return texts_.at(name);
}

const Option& Options::declared(const std::string& name, OptionKind kind) const {
    const Option* o = table_ ? find(*table_, name) : nullptr;
    if (!o || o->kind != kind) {
        std::fprintf(stderr, "pbdsplat: bug: option --%s is read as another kind than its command's table declares (or not "
                             "declared); fix the table or the read\n", name.c_str());
        std::abort();
    }
    return *o;
}

} // namespace pbdsplat::cli
