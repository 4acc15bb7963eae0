#pragma once
// How far a simulated body is from what it should be, for run-time-against-error figures and
// tests: edge strain, volume error and the position error against a reference run. Templated on
// the body's real type, so a double-precision reference is measured the same way.
#include <cmath>

#include "sim/soft_body.h"

namespace pbdsplat::sim {

// Mean |length - rest| / rest over the distance constraints.
template <class Real>
double mean_edge_strain(const SoftBodyT<Real>& b) {
    double sum = 0.0;
    for (const auto& c : b.distance)
        sum += std::abs((b.particles.x[c.i] - b.particles.x[c.j]).template head<3>().template cast<double>().norm() - c.rest) /
               double(c.rest);
    return b.distance.empty() ? 0.0 : sum / double(b.distance.size());
}

// |V - k V0| / (k V0), volumes and targets summed over the volume constraints.
template <class Real>
double total_volume_error(const SoftBodyT<Real>& b) {
    double v = 0.0, target = 0.0;
    for (size_t k = 0; k < b.volumes.size(); ++k) v += b.volume(k), target += double(b.volumes[k].pressure) * b.volumes[k].rest_volume;
    return target > 0.0 ? std::abs(v - target) / target : 0.0;
}

// RMS distance of each particle from the same particle of `reference`, over `scale` (a length
// such as the rest bounding-box diagonal). Both bodies must hold the same particles in one order.
template <class RealA, class RealB>
double rms_position_error(const SoftBodyT<RealA>& body, const SoftBodyT<RealB>& reference, double scale) {
    double sq = 0.0;
    const size_t n = body.particle_count();
    for (size_t i = 0; i < n; ++i)
        sq += (body.particles.x[i].template cast<double>() - reference.particles.x[i].template cast<double>()).squaredNorm();
    return n ? std::sqrt(sq / double(n)) / scale : 0.0;
}

} // namespace pbdsplat::sim
