#pragma once
// Surfaces passing through each other: the figure `pbdsplat check` reports as crossing_ratio.
// penetration_max measures depth inside a closed piece; a torn skin is open and a piece's own
// fold has no inside, so neither is seen there. A crossing is seen on any surface: an edge of one
// triangle passing through another triangle.
#include <cstddef>
#include <vector>

#include "sim/soft_body.h"

namespace pbdsplat::sim {

struct Crossings {
    size_t triangles = 0;  // live triangles an edge of another passes through, or whose edge passes through another
    size_t pairs = 0;      // crossing pairs
    size_t self_pairs = 0; // of those, the pairs within one piece (a fold through itself)
    double ratio = 0.0;    // triangles over the body's live triangles
};

// Pairs sharing a particle, or a rest place (the two copies a cut made of one vertex), do not
// count; nor do pairs that already crossed at rest where the body keeps rest positions (parts of
// a model made to overlap: an eye through its socket).
Crossings surface_crossings(const SoftBody& body);

// Two models (body.model_of_particle) whose surfaces cross as they were placed at load: contact
// leaves what lay inside another at rest alone (it is how a model's own parts are made), so two
// bodies placed into each other stay so.
struct ModelOverlap {
    uint32_t a = 0, b = 0;  // models, a < b
    size_t pairs = 0;       // triangle pairs crossing
};
std::vector<ModelOverlap> models_crossing_at_rest(const SoftBody& body);

} // namespace pbdsplat::sim
