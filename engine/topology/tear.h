#pragma once
// Tearing: an edge stretched past a threshold opens a short slit across itself through the
// same machinery as a line cut. One call tears one edge; a tear grows over frames as the
// strain concentrates at its tips, with a cap on splits per frame so it never shatters the
// body in one step.
#include <optional>
#include <vector>

#include "core/result.h"
#include "sim/soft_body.h"
#include "topology/cut.h"

namespace pbdsplat::topology {

struct TearOptions {
    float threshold = 1.5f;      // current / rest length beyond which an edge tears (> 1)
    uint32_t max_per_frame = 4;  // tears per frame
    float reach = 1.0f;          // the slit reaches at least this many torn-edge lengths (and the vertex's ring)
};
core::Status validate(const TearOptions& options);

struct StrainedEdge {
    uint32_t i = 0, j = 0;
    float ratio = 1.0f;  // current / rest length
};
// The distance constraints stretched beyond `threshold`, most strained first, at most `limit`.
std::vector<StrainedEdge> strained_edges(const sim::SoftBody& body, float threshold, size_t limit);

// Tears at the most strained edge that can open: one of its end vertices is split by the plane
// through it normal to the edge (a pinned end never is). Nothing when no edge passes.
core::Result<std::optional<TopologyChange>> tear_once(sim::SoftBody& body, const TearOptions& tear, const CutOptions& cut);

} // namespace pbdsplat::topology
