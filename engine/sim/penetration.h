#pragma once
// How deep particles lie inside other pieces: the figure `pbdsplat check` reports as
// penetration_max. A particle is inside a closed piece (one with a volume constraint that no
// burst opened: its triangles and the fans that close its cap loops) when the
// piece's generalised winding number at the particle exceeds one half; its depth is then its
// distance to that piece's surface.
// The winding number decides inside or out from the whole closed surface, so a particle that
// fell right through a cut face and sits deep in the piece below counts at its true depth: a
// test against the nearest triangles only (what the contact search sees) cannot tell that
// from a particle just outside the far side.
#include <cstdint>
#include <limits>

#include "sim/closed_surface.h"
#include "sim/soft_body.h"

namespace pbdsplat::sim {

struct Penetration {
    float depth = 0.0f;  // metres; 0 when no particle is inside another piece
    uint32_t particle = std::numeric_limits<uint32_t>::max();
    uint32_t piece = std::numeric_limits<uint32_t>::max();  // the piece it is inside
};

// The deepest particle inside a closed piece other than its own, leaving out particles that
// lay inside that piece at rest already, and the parts of a model that lay partly inside it
// (an eye in its socket, a lid in its pot: contact leaves them to their own shells). A piece's
// own surface is not tested (a fold of one piece through itself is not seen).
// `faces`, where given, spans a cap loop as it is drawn and met (the triangles over the body's
// particles, or null: the loop's least-area span), so a face a second cut folded is measured
// folded.
Penetration deepest_penetration(const SoftBody& body, const FaceLookup& faces = {});

} // namespace pbdsplat::sim
