#include "sim/rigid_response.h"

#include <Eigen/LU>

namespace pbdsplat::sim {

template <class Real>
void RigidResponseT<Real>::map(const std::vector<ShapeCluster>& clusters, std::span<const Real> inverse_mass, float shape_stiffness) {
    // Called every substep: a body without shape matching (a balloon) pays nothing.
    if (clusters.empty()) {
        of_.clear(), frame_.clear(), is_touched_.clear(), touched_.clear();
        any_ = false;
        return;
    }
    of_.assign(inverse_mass.size(), k_none);
    frame_.assign(clusters.size(), Frame{});
    is_touched_.assign(clusters.size(), 0);
    touched_.clear();
    any_ = false;
    for (size_t c = 0; c < clusters.size(); ++c) {
        const std::vector<uint32_t>& members = clusters[c].particles;
        if (members.size() < 4) continue;
        bool free = true;
        for (uint32_t i : members) free = free && i < inverse_mass.size() && inverse_mass[i] > Real(0);
        if (!free) continue;
        if (stiffness_of(clusters[c], shape_stiffness) < k_rigid_response_stiffness) {
            for (uint32_t i : members) of_[i] = k_soft;
            continue;
        }
        for (uint32_t i : members) of_[i] = uint32_t(c);
        any_ = true;
    }
}

template <class Real>
void RigidResponseT<Real>::begin(const std::vector<ShapeCluster>& clusters, const ParticlesT<Real>& p, std::span<const uint32_t> touch) {
    for (uint32_t c : touched_) is_touched_[c] = 0;
    touched_.clear();
    for (uint32_t c : touch)
        if (c < is_touched_.size() && !is_touched_[c]) is_touched_[c] = 1, touched_.push_back(c);
    for (uint32_t c : touched_) {
        Frame& f = frame_[c];
        double mass = 0.0;
        Eigen::Vector3d moment = Eigen::Vector3d::Zero();
        for (uint32_t i : clusters[c].particles) {
            const double m = 1.0 / double(p.w[i]);
            mass += m;
            moment += m * p.x[i].template head<3>().template cast<double>();
        }
        const Eigen::Vector3d centre = moment / mass;
        Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
        for (uint32_t i : clusters[c].particles) {
            const Eigen::Vector3d r = p.x[i].template head<3>().template cast<double>() - centre;
            inertia += (r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose()) / double(p.w[i]);
        }
        // Particles along a line have no inertia about it: a thousandth of the largest keeps the
        // inverse finite (such a cluster barely turns about that axis).
        inertia += 1e-3 * inertia.trace() / 3.0 * Eigen::Matrix3d::Identity();
        f.centre = centre.cast<float>();
        f.inverse_mass = float(1.0 / mass);
        f.inverse_inertia = inertia.inverse().cast<float>();
        f.shift = f.turn = f.settle_shift = f.settle_turn = Vec3f::Zero(), f.votes = 0;
    }
}

template <class Real>
float RigidResponseT<Real>::inverse_mass(uint32_t c, const Vec3f& point, const Vec3f& dir) const {
    const Frame& f = frame_[c];
    const Vec3f rn = (point - f.centre).cross(dir);
    return f.inverse_mass + rn.dot(f.inverse_inertia * rn);
}

template <class Real>
void RigidResponseT<Real>::push(uint32_t c, const Vec3f& point, const Vec3f& impulse, bool vote, float settle) {
    Frame& f = frame_[c];
    f.votes += vote ? 1u : 0u;
    const Vec3f shift = f.inverse_mass * impulse, turn = f.inverse_inertia * (point - f.centre).cross(impulse);
    f.shift += shift, f.turn += turn;
    f.settle_shift += settle * shift, f.settle_turn += settle * turn;
}

template <class Real>
void RigidResponseT<Real>::finish(const std::vector<ShapeCluster>& clusters, ParticlesT<Real>& p) {
    for (uint32_t c : touched_) {
        Frame& f = frame_[c];
        if (f.votes == 0) continue;
        const float mean = 1.0f / float(f.votes);
        // The turn is first order (x + turn x r): past a tenth of a radian it would stretch the
        // cluster by over half a per cent a sweep, so a larger one is taken a tenth at a time.
        const float turned = mean * f.turn.norm(), spin = turned > k_max_turn ? k_max_turn / turned : 1.0f;
        const Vec3f shift = mean * f.shift, turn = spin * mean * f.turn, settle_shift = mean * f.settle_shift, settle_turn = spin * mean * f.settle_turn;
        const bool settle = !settle_shift.isZero() || !settle_turn.isZero();
        for (uint32_t i : clusters[c].particles) {
            const Vec3f r = p.x[i].template head<3>().template cast<float>() - f.centre;
            p.x[i] += to4<Real>(shift + turn.cross(r));
            if (settle) p.x_prev[i] += to4<Real>(settle_shift + settle_turn.cross(r));
        }
        f.centre += shift;
        f.shift = f.turn = f.settle_shift = f.settle_turn = Vec3f::Zero(), f.votes = 0;
    }
}

template class RigidResponseT<float>;
template class RigidResponseT<double>;

} // namespace pbdsplat::sim
