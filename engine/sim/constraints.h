#pragma once
// Constraint data. Definitions never change after creation, except their particle indices (the
// topology stage re-points them when a cut duplicates vertices).
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "core/math.h"

namespace pbdsplat::sim {

// ||x_i - x_j|| - rest = 0 (paper eq. 6).
struct DistanceConstraint {
    uint32_t i, j;
    float rest;
    float compliance;  // XPBD compliance (inverse stiffness, m/N); PBD mode uses the global stiffness
    // A slot emptied by a topology edit (i == j, rest 0) costs the solver a skipped iteration
    // until the slot is reused or the constraints are regrouped; readers skip it.
    bool alive() const { return i != j; }
};
static_assert(sizeof(DistanceConstraint) == 16, "four distance constraints per cache line");

// V - k*V0 = 0 over one closed (or virtually capped) piece of the body (paper eqs. 7 and 9).
// It names its piece, not its triangles: the gradient is gathered from the body's own vertex
// rings over the particles labelled with that piece (SoftBody::piece_of_particle), so a cut
// that splits a piece relabels particles instead of copying per-piece triangle lists.
struct VolumeConstraint {
    uint32_t piece = 0;
    size_t triangle_count = 0;  // of its piece when it was made (a change that kept it keeps its target)
    // Boundary loops closed by virtual fans to their centroid, in the volume sum only, so the
    // volume of an open piece does not depend on where the origin is.
    std::vector<std::vector<uint32_t>> cap_loops;
    // Per cap loop, once the topology stage has needed them: its rest-space bounding sphere
    // (centre xyz, radius w), so a cut finds the loops it reaches without reading every loop.
    // Empty, or one per loop.
    std::vector<Vec4f> cap_bounds;
    double rest_volume = 0.0;  // V0, measured at creation
    float pressure = 1.0f;     // k: target volume k * V0 (deflate < 1 < inflate)
    float compliance = 0.0f;   // XPBD
    double lambda = 0.0;       // XPBD multiplier, reset every substep
    // 6V of its piece's triangles (caps apart) at the solver's last volume pass (NaN: not yet):
    // a cut that leaves the piece whole takes the piece's volume from here instead of summing
    // the whole piece again.
    double measured_six_v = std::numeric_limits<double>::quiet_NaN();
    // The caps' 6V at that pass: with it, a cut that leaves the piece whole reads the caps of the
    // loops it did not reach from here instead of summing every loop again.
    double measured_caps_six_v = std::numeric_limits<double>::quiet_NaN();
    // An opened component (burst) leaks: its gas escapes through its openings, k falling toward
    // empty at up to this rate (1/s), in proportion to the openings' area while they are small
    // (sim::leak_rate): a slit whose sides still touch holds its pressure, so the strain that
    // opened it stays to run it on, and a rip opened wide empties the body within a second. Gradual,
    // not at once: a target dropped in one frame snapped the stretched shell inward and imploded
    // it. k settles at k_emptied, the bulk of the crumpled skin: with nothing to hold it, the skin
    // (edges without bending or self-contact) kept folding inward on the speed the drain gave it
    // until it was a knot (a ball's volume at 0.08 of its own 3 s after the burst). 0: sealed.
    float leak = 0.0f;
    // Particles below this index were there when the body was made: a loop of them only is one of
    // the model's own holes, capped at load and holding air; any other loop is an opening.
    uint32_t sealed_below = 0;
    static constexpr float k_emptied = 0.3f;
    bool is_opening(std::span<const uint32_t> loop) const {
        for (uint32_t i : loop)
            if (i >= sealed_below) return true;
        return false;
    }
    bool opened() const {
        for (const auto& loop : cap_loops)
            if (is_opening(loop)) return true;
        return false;
    }
    // Emptied: open to the air, at the skin's own bulk (contact treats the piece as open).
    bool leaking_done() const { return leak > 0.0f && pressure <= k_emptied + 0.02f; }
};

// Pulls a region of the surface toward a moving target: the demo's mouse drag and the scenes'
// drag events. The region moves as one (each particle toward the target plus its offset from the
// grab point when it was taken), at full weight over its inner half and fading to nothing at its
// rim, so what is held stretches the body around it instead of plucking one particle out.
struct DragConstraint {
    std::vector<uint32_t> particles;
    std::vector<Vec3f> offsets;   // from the grab point, when the region was taken
    std::vector<float> weights;   // fraction of the gap closed per iteration, in (0, 1]
    Vec3f target = Vec3f::Zero();  // where the grab point is pulled
    bool active = false;
};

} // namespace pbdsplat::sim
