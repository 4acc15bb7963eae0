#pragma once
// What a torn body still encloses and how long its openings are: the figures of a burst. A
// balloon that bursts loses its volume; a tear that runs lengthens the rim of its opening.
#include "sim/penetration.h"
#include "sim/soft_body.h"

namespace pbdsplat::sim {

struct OpeningReport {
    // The volume inside the triangles, every open loop closed by its drawn cut face where `faces`
    // gives one (folded where a later cut crossed it), else by a fan at its centroid (a slit whose
    // two sides still touch closes to nothing; a rip opened wide closes over its hole).
    double volume = 0.0;
    // The open edges (used by one triangle) measured at rest, in mean rest edge lengths: both
    // sides of a slit count, so a slit of 10 edges reads about 20.
    double open_length = 0.0;
};

// A fan across a loop over two cut planes is no face: a ball cut in quarters read 1.32 of its
// volume, and a third cut took it below zero.
OpeningReport opening_report(const SoftBody& body, const FaceLookup& faces = {});

} // namespace pbdsplat::sim
