#pragma once
// One table of names per enum: the scene reader, the scene writer, the command line and the
// reports all read the same table, so a name cannot be spelled two ways.
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace pbdsplat::core {

template <class E>
struct EnumName {
    E value;
    const char* name;
};

template <class E>
const char* name_of(std::span<const EnumName<E>> table, E value) {
    for (const auto& e : table)
        if (e.value == value) return e.name;
    return "?";
}

template <class E>
std::optional<E> from_name(std::span<const EnumName<E>> table, std::string_view name) {
    for (const auto& e : table)
        if (name == e.name) return e.value;
    return std::nullopt;
}

// The names in table order (what a parser offers as choices).
template <class E>
std::vector<std::string> names_of(std::span<const EnumName<E>> table) {
    std::vector<std::string> out;
    for (const auto& e : table) out.emplace_back(e.name);
    return out;
}

} // namespace pbdsplat::core
