#pragma once
// A stiff body answers a contact as one body: a push on one of its particles moves its whole
// shape cluster (a translation and a small turn about its centre, by the cluster's mass and
// inertia), not the particle alone.
//
// Why: answered particle by particle, a body resting on a point (a bunny on a teapot's knob, a
// block on another's corner) is held up by the few particles over the point. Shape matching pulls
// those back into the body's shape a fraction of the way each iteration, slower than the body's
// weight presses them in, so the point sinks into the body (a bunny 4.6 spacings deep on the
// knob). A rigid answer carries the whole weight at the point, as a solid does.
//
// A sweep answers every pair against the clusters as they were at its start and moves each
// cluster by the mean of its pairs' answers (Jacobi, averaged): answered one pair after another,
// the first pairs of a resting face took its whole weight every substep, and their torque, always
// the same way, tipped the pieces of a cut bunny over (60 degrees). A touched cluster costs two
// passes over its particles at the substep's start (centre and inertia, which turn too little
// within a substep to matter) and one at the end of each sweep.
#include <cstdint>
#include <span>
#include <vector>

#include "core/math.h"
#include "sim/particles.h"
#include "sim/shape.h"

namespace pbdsplat::sim {

// Shape matching at least this stiff makes a body answer contact as one. A softer body is
// meant to give where it is pressed (a balloon, a soft toy), so its particles answer alone.
inline constexpr float k_rigid_response_stiffness = 0.5f;
// The most a cluster turns in one sweep, in radians (see finish()).
inline constexpr float k_max_turn = 0.1f;

template <class Real>
class RigidResponseT {
public:
    static constexpr uint32_t k_none = UINT32_MAX;
    // A particle of a free cluster softer than k_rigid_response_stiffness: what it meets answers
    // particle by particle too (a stiff ball answering a soft cushion as a whole pressed its
    // weight into the few particles under it, crushed the cushion and burst through it).
    static constexpr uint32_t k_soft = UINT32_MAX - 1;

    // Which cluster each particle answers with: none for a particle in no cluster, or in one with
    // a pinned particle (held by the scene, not free to move as one), under four particles or
    // softer than k_rigid_response_stiffness (`shape_stiffness`: the settings', for clusters of
    // no stiffness of their own).
    void map(const std::vector<ShapeCluster>& clusters, std::span<const Real> inverse_mass, float shape_stiffness = 1.0f);
    uint32_t cluster_of(uint32_t particle) const { return particle < of_.size() ? of_[particle] : k_none; }
    bool any() const { return any_; }
    bool soft(uint32_t particle) const { return cluster_of(particle) == k_soft; }

    // Before a substep's first sweep: the clusters `touch` names (repeats allowed) take their
    // centres, masses and inertias from the particles as they are.
    void begin(const std::vector<ShapeCluster>& clusters, const ParticlesT<Real>& p, std::span<const uint32_t> touch);
    // The inverse mass cluster `c` shows at `point` along the unit `dir`: 1/M + (r x d)^T I^-1 (r x d).
    float inverse_mass(uint32_t c, const Vec3f& point, const Vec3f& dir) const;
    // A position impulse (mass times displacement) on cluster `c` at `point`; `vote`: a pair's
    // first, which counts it among those the cluster's motion is the mean of. The `settle` share
    // of it moves the substep's start positions too, so it sets nothing moving (an overlap that
    // was there when the substep began: see ContactSolver::separate).
    void push(uint32_t c, const Vec3f& point, const Vec3f& impulse, bool vote, float settle = 0.0f);
    // After a sweep: moves every particle of the touched clusters by the mean of its pairs' answers.
    void finish(const std::vector<ShapeCluster>& clusters, ParticlesT<Real>& p);

private:
    struct Frame {
        Vec3f centre = Vec3f::Zero();
        float inverse_mass = 0.0f;
        Eigen::Matrix3f inverse_inertia = Eigen::Matrix3f::Zero();
        Vec3f shift = Vec3f::Zero();  // summed translations
        Vec3f turn = Vec3f::Zero();   // summed small rotations (axis times angle)
        Vec3f settle_shift = Vec3f::Zero(), settle_turn = Vec3f::Zero();  // of those, what moves the start too
        uint32_t votes = 0;
    };
    std::vector<uint32_t> of_;
    std::vector<Frame> frame_;
    std::vector<uint32_t> touched_;
    std::vector<uint8_t> is_touched_;
    bool any_ = false;
};

using RigidResponse = RigidResponseT<float>;

} // namespace pbdsplat::sim
