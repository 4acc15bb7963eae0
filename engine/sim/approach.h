#pragma once
// How many substeps a frame needs for what is about to meet. Contact keeps a particle on the side
// of a surface it started the substep on, but only among the nearest candidates the search found
// around where it ended: a ball thrown at 25 m/s crossed 0.42 m a step, past the face it met, and
// ended 29 spacings inside the box it hit. Where two pieces close on each other faster than half
// a rest edge a step, the frame is cut into enough substeps that they do not.
#include <cstdint>

#include "sim/rigid_response.h"
#include "sim/soft_body.h"
#include "sim/solver.h"

namespace pbdsplat::sim {

// Whether a frame's substeps follow what closes in: for stiff bodies (those contact answers as
// wholes). A soft body's stiffness hangs on its substeps (PBD converges per step), so a balloon
// stepped finer as its torn scraps flew about tore 88 times instead of 141 and crumpled
// otherwise: its frames keep the scene's substeps.
template <class Real>
bool approach_steps(const SolverSettings& s, const SoftBodyT<Real>& body) {
    return s.contact.enabled && s.contact.approach && stiffest_shape(body.shapes, s.shape_stiffness) >= k_rigid_response_stiffness;
}

// The substeps (a power of two, 1 to `most`) in which no two pieces whose paths over the frame
// `dt` meet close on each other by more than half of `edge` a substep, from the mean velocities of
// their particles now. Beyond k_approach_pieces pieces (a heap of crushed flakes) it answers 1: the
// pairs would cost more than they save.
template <class Real>
uint32_t approach_substeps(const SoftBodyT<Real>& body, float dt, float edge, uint32_t most);
inline constexpr size_t k_approach_pieces = 128;
// At most this many substeps a frame for speed (a piece thrown at 25 m/s at the demo's 60 Hz
// and a 0.067 m edge needs 13).
inline constexpr uint32_t k_max_approach_substeps = 16;

// A frame's substeps: the settings' own, the contact's while pieces are stacked, and more while
// stiff pieces close in fast (approach_substeps), the raised counts kept within `max_sweeps`
// iterations a frame.
template <class Real>
uint32_t frame_substeps(const SolverSettings& s, const SoftBodyT<Real>& body, const ContactSolverT<Real>& contact, float dt,
                        uint32_t max_sweeps);

} // namespace pbdsplat::sim
