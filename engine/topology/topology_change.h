#pragma once
// The before/after record of one topology change, so that the surface, mapping and upload
// stages react only to what changed and the cost can be reported (paper Tables 2-4).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "mesh/triangle_split.h"

namespace pbdsplat::topology {

struct TopologyChange {
    size_t particles_before = 0, particles_after = 0;
    size_t triangles_before = 0, triangles_after = 0;
    size_t components_before = 0, components_after = 0;
    size_t crossed_edges = 0;       // edges split by a new particle (eq. 26)
    size_t crossed_triangles = 0;   // triangles re-triangulated (eq. 27)
    size_t duplicated_vertices = 0; // copies made so the sides separate (eq. 28)
    size_t constraints_removed = 0, constraints_added = 0;  // distance constraints re-made
    bool headroom_grown = false;    // the body's arrays were moved to make room (amortised)
    bool loops_fell_back = false;   // the boundary loops were counted over whole pieces (a local trace failed)
    size_t particles_searched = 0;  // by the search for the parts of the pieces the change reached
    size_t searched_whole = 0;      // reached pieces that search could not settle locally (swept whole)
    size_t summed_whole = 0;        // pieces kept whole whose volume took a pass over the body (no solver measure yet)
    // Children of every re-triangulated triangle; triangles not listed kept their index.
    std::vector<mesh::TriangleSplit> splits;
    // Triangles whose corners or shape changed (children and re-pointed ones), new indices.
    std::vector<uint32_t> touched_triangles;
    float min_child_area_ratio = 1.0f;  // smallest child / parent rest area: no slivers
    double ms = 0.0;          // the whole change
    double rebuild_ms = 0.0;  // of which: solver data derived from the new lists
    // Where the time went, step by step in the order run (names are static strings), so a
    // benchmark can show which step grows with the body rather than with the cut.
    struct Phase {
        const char* name;
        double ms;
    };
    std::vector<Phase> phases;

    bool changed() const { return particles_after != particles_before || triangles_after != triangles_before; }
    // Particles [particles_before, particles_after) are new.
    size_t new_particles() const { return particles_after - particles_before; }
};

} // namespace pbdsplat::topology
