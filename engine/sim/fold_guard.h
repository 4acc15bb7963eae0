#pragma once
// A crumpling skin kept from folding through its own neighbourhood. Contact leaves a particle's
// own surface within a few edges alone (at rest it lies on it: sim/contact.h), yet that is where
// a deflating balloon creases and lays one fold through the next (docs/BENCHMARKS.md, "Surfaces
// through each other"). There, nearness says nothing; passing through does. Each substep pairs
// every particle with the triangles of its rest neighbourhood (not its own fan) that it lies over
// or near; each iteration keeps it on the side of the triangle it was on when the substep began,
// at a fraction of the contact thickness. A particle at rest lies beside its neighbours'
// triangles, never over them, so a resting or smoothly bending surface is never pushed: only a
// fold closing on itself is.
#include <cstdint>
#include <vector>

#include "sim/contact.h"
#include "sim/soft_body.h"

namespace pbdsplat::sim {

// The gap a fold keeps, over the mean rest edge: well under the splats' size (half an edge), so a
// crease shows no seam, and enough that a particle pushed to it does not cross back by rounding.
inline constexpr float k_fold_thickness = 0.1f;

template <class Real>
class FoldGuardT {
public:
    // After prediction: the pairs that may meet this substep. Nothing for stiff bodies (their
    // pieces keep their shape and never fold) or without contact.
    void find(const SoftBodyT<Real>& body, const ContactSettings& s, bool stiff_bodies);
    // One sweep over them (every iteration).
    void project(ParticlesT<Real>& p) const;

    // Rest-neighbourhood pairs known, and this substep's candidates among them.
    size_t pairs() const { return near_.size(); }
    size_t candidates() const { return active_.size(); }

private:
    struct Candidate {
        uint32_t particle;
        uint32_t a, b, c;  // the triangle's corners
        float side;  // +1 in front of the triangle at the substep's start, -1 behind
    };
    bool stale(const SoftBodyT<Real>& body, const ContactSettings& s) const;
    void build(const SoftBodyT<Real>& body, const ContactSettings& s);
    void gather(const SoftBodyT<Real>& body, uint32_t i, float radius);
    void frame_triangles(const SoftBodyT<Real>& body);

    // Per particle, the live triangles of its piece within `radius_` of it at rest, not its own
    // (CSR: near_[start_[i] .. start_[i + 1]]); rebuilt when the topology changes.
    std::vector<uint32_t> start_, near_;
    size_t built_particles_ = 0, built_triangles_ = 0, built_pieces_ = 0;
    float settings_thickness_ = 0.0f;
    ContactScale scale_;  // the body's, as last built
    std::vector<uint32_t> vertex_stamp_, triangle_stamp_, queue_;  // build scratch
    // Per triangle this substep: its bounding sphere (radius < 0: dead or degenerate) and its
    // plane (unit normal, offset) predicted, and its plane at the substep's start.
    struct TriangleFrame {
        Vec4f sphere, plane, plane0;
    };
    std::vector<TriangleFrame> frames_;
    float on_ = 0.0f;         // within this of a triangle at rest, a particle lies on it
    float thickness_ = 0.0f;  // kept between a fold's layers
    std::vector<Candidate> active_;
};
using FoldGuard = FoldGuardT<float>;

} // namespace pbdsplat::sim
