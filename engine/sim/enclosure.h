#pragma once
// Parts of a body that lay wholly inside another closed part when it was built: a stone in a
// fruit, a box's inner lining modelled as a surface of its own, a model placed inside a closed
// container. Contact keeps such a part on the inside of its container (sim/contact.h). Parts that
// lie only partly in each other (an eye in its socket, a lid in its pot) are not enclosed:
// contact leaves those to their own shells.
#include <algorithm>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "sim/soft_body.h"

namespace pbdsplat::sim {

// (inner part, outer part) pairs, sorted: every particle of the inner part (up to
// k_enclosure_samples of them, spread over it) lies inside the outer part's closed surface at
// rest, by its winding number. A part in two nested containers is paired with both.
inline constexpr size_t k_enclosure_samples = 32;
std::vector<std::pair<uint32_t, uint32_t>> find_enclosed_parts(const SoftBody& body);

// Whether `inner` lay wholly inside `outer` (`pairs` as find_enclosed_parts returns them).
inline bool part_encloses(std::span<const std::pair<uint32_t, uint32_t>> pairs, uint32_t outer, uint32_t inner) {
    return std::binary_search(pairs.begin(), pairs.end(), std::pair<uint32_t, uint32_t>(inner, outer));
}

} // namespace pbdsplat::sim
