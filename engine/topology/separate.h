#pragma once
// Topology change on a soft body: separating it along a cut surface by duplicating the vertices
// whose triangles lie on both sides (paper eq. 28), then re-indexing the constraints into the
// components that result. This first version cuts along existing mesh edges: triangles are
// assigned to a side whole, so the cut follows the triangles' boundaries; the edge-intersection
// re-triangulation of eqs. 26-27 refines it later without changing this interface.
#include <functional>
#include <vector>

#include "core/result.h"
#include "sim/soft_body.h"

namespace pbdsplat::topology {

// What a topology change did, so that the surface, mapping and upload stages react only to it.
struct TopologyChange {
    size_t split_vertices = 0;    // vertices duplicated
    size_t new_particles = 0;
    size_t touched_triangles = 0;  // triangles whose corners were re-pointed
    size_t components_before = 0, components_after = 0;
    double ms = 0.0;
};

// side(t) says which side triangle t is on; splittable(v) whether vertex v may be duplicated
// (a cut ending inside the surface stops where the vertices are no longer splittable). The
// total mass is kept: a duplicated particle's mass is shared between its copies. Each
// resulting component gets its own volume constraint, with V0 re-measured (capped) at the
// moment of the cut.
core::Result<TopologyChange> separate(sim::SoftBody& body, const std::function<bool(uint32_t triangle)>& side,
                                      const std::function<bool(uint32_t vertex)>& splittable);

// Invariants every topology change must keep; an error names the first one broken.
core::Status check_invariants(const sim::SoftBody& body);

} // namespace pbdsplat::topology
