#pragma once
// What every topology change must keep (checked after each change in debug builds and tests).
#include "core/result.h"
#include "sim/soft_body.h"

namespace pbdsplat::topology {

struct InvariantOptions {
    // Smallest rest area a triangle may have, as a fraction of the mean rest triangle area.
    float min_area_ratio = 1e-4f;
};

// Checks, naming the first one broken: particle arrays of one length and finite; triangles of
// three distinct live particles above the minimum area; manifold with boundary (an undirected
// edge in at most two triangles, used once in each direction: consistent orientation); no
// bow-tie (every vertex's triangles form one fan); every distance constraint on an edge of the
// surface; every volume constraint over live particles of a single component; then check_derived.
core::Status check_invariants(const sim::SoftBody& body, const InvariantOptions& options = {});

// The data topology edits keep up to date incrementally, against the same made from scratch:
// the vertex rings and their triangle lists equal a full build; the distance colour groups are
// valid (no two live constraints of a group share a particle, the per-particle index lists
// exactly the live ones); the piece count equals a component count; every volume constraint's
// vertices and rings equal a fresh build of them, and its cap loops are its piece's boundary
// loops (as cycles, in the same direction).
core::Status check_derived(const sim::SoftBody& body);

struct MeshCounts {
    size_t components = 0, boundary_loops = 0;
};
MeshCounts count_components_and_loops(const sim::SoftBody& body);

} // namespace pbdsplat::topology
