#pragma once
// How far a body has drifted from its rest shape, ignoring where it is and how it is turned:
// per connected piece, the RMS distance of its particles from their rest positions after the
// best rigid alignment (Kabsch), over the piece's rest bounding-box diagonal. A piece moved
// rigidly scores 0; a bunny melted into a puddle scores about 0.2.
#include <cstddef>
#include <vector>

#include "sim/soft_body.h"

namespace pbdsplat::sim {

struct PieceShape {
    size_t particles = 0;
    double error = 0.0;          // RMS after alignment / rest diagonal
    double volume_error = 0.0;   // |V / V0 - 1| of the piece's volume constraint, when it has one
};

struct ShapeReport {
    std::vector<PieceShape> pieces;  // every connected piece, largest first
    double max_error = 0.0;          // over pieces of at least `min_particles`
};

// Pieces smaller than `min_particles` (a torn-off flake) are listed but not counted in the max:
// a handful of particles has no shape to keep.
ShapeReport shape_report(const SoftBody& body, size_t min_particles = 8);

// The most any edge is stretched: its present length over its rest length, over the live distance
// constraints, a rest length under the mean taken as the mean (at most 1 for a body at rest; about
// 1.6 for a balloon blown to four times its volume). A surface gone wrong (a sheet or spike shot
// out of a body) reads here when its splats still lie on it and count as no strays. 0 for a body
// without edges.
double edge_stretch_max(const SoftBody& body);

} // namespace pbdsplat::sim
