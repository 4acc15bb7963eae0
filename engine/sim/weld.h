#pragma once
// Welds: the parts of one model that touch at rest but share no vertex (a teapot's spout, handle
// and lid lie on its body as separate surfaces) held together, so that a model a user loads
// behaves as the one object it shows instead of shedding its parts. A weld is a distance
// constraint between two particles of different parts, at their rest distance, and welded parts
// share one shape-matching cluster (sim/shape.h). Welds are not mesh edges: a cut severs those it
// passes between (topology/cut.cpp), a tear runs through the skin beside them.
#include <cstddef>
#include <span>
#include <vector>

#include "sim/soft_body.h"

namespace pbdsplat::sim {

// Which parts a weld may start from.
enum class WeldFrom {
    // Open parts only, from their open edges: a spout's end to the body it stands on, a lid's
    // rim to the pot's. Closed parts that touch (a model's eyeballs in their sockets) are left
    // apart: held to a balloon head that deflates and re-inflates, suzanne's eyes tore its
    // surface apart (volume error 9, measured).
    open_edges,
    // Also every surface particle of a closed part: for a body that keeps a shape (shape
    // matching on), a table modelled as a top on four closed legs is one table (left apart, the top slid down
    // between its legs, which contact leaves alone where parts lay on each other at load).
    open_edges_and_closed_parts,
};

// Adds a weld from every particle `from` admits to the nearest particle of another part of its
// model within `reach` (where the particles are at the call), once per pair. Returns how many.
size_t weld_touching_parts(SoftBody& body, float reach, WeldFrom from = WeldFrom::open_edges);
// The same with each model's own reach (`reach_of_model[m]` for model m): a scene's models
// differ in size, and one mean edge over all of them (a small bunny's beside a teapot's) left
// the larger model's lid unwelded.
size_t weld_touching_parts(SoftBody& body, std::span<const float> reach_of_model, WeldFrom from = WeldFrom::open_edges);
// Per model: the mean rest length of the live distance constraints within it (0 for a model
// without any), the reach weld_touching_parts takes.
std::vector<float> mean_rest_edge_of_models(const SoftBody& body);

// Projects every weld once (PBD, `stiffness` of the error), one after another.
template <class Real>
void project_welds(const BodyStructureT<Real>& body, ParticlesT<Real>& p, Real stiffness);

} // namespace pbdsplat::sim
