#include "pbdsplat/args.h"

#include <charconv>
#include <cmath>

namespace pbdsplat::cli {

core::Result<Args> Args::parse(const std::vector<std::string>& argv, const std::set<std::string>& flags,
                               const std::set<std::string>& options) {
    Args a;
    for (size_t i = 0; i < argv.size(); ++i) {
        const std::string& arg = argv[i];
        if (arg.rfind("--", 0) != 0 || arg == "--") {
            a.positionals_.push_back(arg);
            continue;
        }
        std::string name = arg.substr(2), value;
        const size_t eq = name.find('=');
        const bool inline_value = eq != std::string::npos;
        if (inline_value) value = name.substr(eq + 1), name = name.substr(0, eq);
        if (flags.count(name)) {
            if (inline_value) return core::make_error("--" + name + " takes no value");
            a.flags_.insert(name);
        } else if (options.count(name)) {
            if (!inline_value) {
                if (i + 1 >= argv.size()) return core::make_error("--" + name + " needs a value");
                value = argv[++i];
            }
            a.values_[name] = value;
        } else {
            return core::make_error("unknown option --" + name + " (see --help)");
        }
    }
    return a;
}

std::optional<std::string> Args::get(const std::string& name) const {
    auto it = values_.find(name);
    if (it == values_.end()) return std::nullopt;
    return it->second;
}

std::string Args::get_or(const std::string& name, const std::string& fallback) const {
    return get(name).value_or(fallback);
}

core::Result<uint32_t> Args::get_uint(const std::string& name, uint32_t fallback, uint32_t min, uint32_t max) const {
    auto v = get(name);
    if (!v) return fallback;
    uint64_t out = 0;
    const auto [end, ec] = std::from_chars(v->data(), v->data() + v->size(), out);
    if (ec != std::errc() || end != v->data() + v->size())
        return core::make_error("--" + name + " expects a whole number, got '" + *v + "'");
    if (out < min || out > max)
        return core::make_error("--" + name + " must be between " + std::to_string(min) + " and " + std::to_string(max) +
                                ", got " + *v);
    return uint32_t(out);
}

core::Result<float> Args::get_float(const std::string& name, float fallback, float min, float max) const {
    auto v = get(name);
    if (!v) return fallback;
    float out = 0.0f;
    const auto [end, ec] = std::from_chars(v->data(), v->data() + v->size(), out);
    if (ec != std::errc() || end != v->data() + v->size() || !std::isfinite(out))
        return core::make_error("--" + name + " expects a number, got '" + *v + "'");
    if (out < min || out > max)
        return core::make_error("--" + name + " must be between " + std::to_string(min) + " and " + std::to_string(max) +
                                ", got " + *v);
    return out;
}

core::Result<std::string> Args::get_choice(const std::string& name, const std::string& fallback,
                                           const std::vector<std::string>& choices) const {
    const std::string v = get_or(name, fallback);
    std::string all;
    for (const auto& c : choices) {
        if (c == v) return v;
        all += (all.empty() ? "" : ", ") + c;
    }
    return core::make_error("--" + name + " must be one of " + all + ", got '" + v + "'");
}

} // namespace pbdsplat::cli
