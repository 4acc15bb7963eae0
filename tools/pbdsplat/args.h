#pragma once
// Command-line arguments of one command: --name value, --name=value, --flag, positionals.
// Every option must be declared, so a typo is an error instead of being ignored.
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "core/result.h"

namespace pbdsplat::cli {

class Args {
public:
    // `flags` take no value; `options` take one.
    static core::Result<Args> parse(const std::vector<std::string>& argv, const std::set<std::string>& flags,
                                    const std::set<std::string>& options);

    bool has(const std::string& name) const { return flags_.count(name) > 0 || values_.count(name) > 0; }
    std::optional<std::string> get(const std::string& name) const;
    std::string get_or(const std::string& name, const std::string& fallback) const;
    core::Result<uint32_t> get_uint(const std::string& name, uint32_t fallback, uint32_t min, uint32_t max) const;
    core::Result<float> get_float(const std::string& name, float fallback, float min, float max) const;
    // One of `choices`, or the fallback when absent.
    core::Result<std::string> get_choice(const std::string& name, const std::string& fallback,
                                         const std::vector<std::string>& choices) const;
    const std::vector<std::string>& positionals() const { return positionals_; }

private:
    std::set<std::string> flags_;
    std::map<std::string, std::string> values_;
    std::vector<std::string> positionals_;
};

// The first of several parsed values that failed (for one usage message), or null.
template <class... T>
const core::Error* first_error(const core::Result<T>&... results) {
    const core::Error* first = nullptr;
    ((first = first ? first : (results.ok() ? nullptr : &results.error())), ...);
    return first;
}

} // namespace pbdsplat::cli
