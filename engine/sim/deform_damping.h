#pragma once
// Damping of each piece's deformation alone: every particle's velocity is drawn toward the
// velocity the piece's rigid motion (its centre's velocity and its spin about the centre) gives
// it there, so a piece's wobble dies while its flight and spin go on (the damping of Müller et
// al., "Position based dynamics", 2007, section 3.5, as a rate per second). Velocity damping
// (SolverSettings::damping) slows both alike; it cannot calm a soft cushion that springs a
// heavy ball back up without slowing everything thrown.
#include <cstdint>
#include <span>
#include <vector>

#include "core/math.h"
#include "sim/particles.h"

namespace pbdsplat::sim {

// Per piece, the sums its rigid motion is read from (double: positions in metres, masses in
// grams, summed over thousands of particles), and that motion.
struct PieceMoments {
    double m = 0.0;
    Eigen::Vector3d mx = Eigen::Vector3d::Zero(), mv = Eigen::Vector3d::Zero(), mxv = Eigen::Vector3d::Zero();
    Eigen::Matrix3d mxx = Eigen::Matrix3d::Zero();  // sum of m x x^T
    Eigen::Vector3d centre = Eigen::Vector3d::Zero(), velocity = Eigen::Vector3d::Zero(), spin = Eigen::Vector3d::Zero();
    double take = 0.0;  // the share of each particle's deviation taken off this substep
};

// Draws the free particles' velocities toward their piece's rigid motion by 1 - e^(-rate h),
// `rate` per piece (1/s; 0 leaves a piece alone). `piece`: each particle's piece, k >= rate.size()
// for none. `scratch` holds the sums between calls.
template <class Real>
void damp_deformation(ParticlesT<Real>& p, std::span<const uint32_t> piece, std::span<const float> rate, Real h,
                      std::vector<PieceMoments>& scratch);

} // namespace pbdsplat::sim
