#include "graph/blackboard.h"

#include "core/assert.h"

namespace pbdsplat::graph {

void Blackboard::put_entry(std::string_view name, std::type_index type, uint32_t version) {
    const auto it = entries_.find(name);
    // A later version of the same resource replaces the earlier; another type under the name is
    // two modules disagreeing about what the name means.
    PBDSPLAT_ASSERT(it == entries_.end() || it->second.type == type,
                    "Blackboard: '" + std::string(name) + "' put as another type than it holds");
    if (it == entries_.end())
        entries_.emplace(std::string(name), Entry{type, version});
    else
        it->second.version = version;
}

core::Status Blackboard::lookup(std::string_view name, std::type_index type, uint32_t& version) const {
    const auto it = entries_.find(name);
    if (it == entries_.end()) return core::make_error("blackboard: no '" + std::string(name) + "' was put");
    if (it->second.type != type)
        return core::make_error("blackboard: '" + std::string(name) + "' holds a " + it->second.type.name() + ", not a " + type.name());
    version = it->second.version;
    return core::Status::success();
}

void Blackboard::require(const core::Status& s) {
    PBDSPLAT_ASSERT(s.ok(), s.ok() ? std::string() : s.error().to_string());
}

} // namespace pbdsplat::graph
