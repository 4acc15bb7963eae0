#include "sim/deform_damping.h"

#include <cmath>


namespace pbdsplat::sim {

namespace {
// Reads a piece's rigid motion off its sums: its centre, the centre's velocity and its spin.
void read_rigid(PieceMoments& s, double share) {
    if (!(s.m > 0.0)) return;
    s.centre = s.mx / s.m, s.velocity = s.mv / s.m, s.take = share;
    // About the centre: L = sum m x*v - M c*v_c, I = sum m (|x|^2 1 - x x^T) - M (|c|^2 1 - c c^T).
    const Eigen::Vector3d L = s.mxv - s.m * s.centre.cross(s.velocity);
    const Eigen::Matrix3d xx = s.mxx - s.m * s.centre * s.centre.transpose();
    const Eigen::Matrix3d I = Eigen::Matrix3d::Identity() * xx.trace() - xx;
    // A piece too thin to spin about some axis (a strand, one particle) keeps no spin: its
    // inertia cannot be inverted safely, and the centre's velocity is the rigid motion there is.
    const double scale = I.trace();
    if (scale > 0.0 && std::abs(I.determinant()) > 1e-9 * scale * scale * scale) s.spin = I.ldlt().solve(L);
}
} // namespace

template <class Real>
void damp_deformation(ParticlesT<Real>& p, std::span<const uint32_t> piece, std::span<const float> rate, Real h,
                      std::vector<PieceMoments>& scratch) {
    const size_t pieces = rate.size();
    scratch.assign(pieces, PieceMoments{});
    for (size_t i = 0; i < p.size(); ++i) {
        const uint32_t k = piece[i];
        if (k >= pieces || !(rate[k] > 0.0f) || !(p.w[i] > Real(0))) continue;
        const double m = 1.0 / double(p.w[i]);
        const Eigen::Vector3d x = p.x[i].template head<3>().template cast<double>(), v = p.v[i].template head<3>().template cast<double>();
        PieceMoments& s = scratch[k];
        s.m += m, s.mx += m * x, s.mv += m * v, s.mxv += m * x.cross(v), s.mxx += m * x * x.transpose();
    }
    for (size_t k = 0; k < pieces; ++k)
        if (rate[k] > 0.0f) read_rigid(scratch[k], 1.0 - std::exp(-double(rate[k]) * double(h)));
    for (size_t i = 0; i < p.size(); ++i) {
        const uint32_t k = piece[i];
        if (k >= pieces || !(scratch[k].take > 0.0) || !(p.w[i] > Real(0))) continue;
        const PieceMoments& r = scratch[k];
        const Eigen::Vector3d x = p.x[i].template head<3>().template cast<double>(), v = p.v[i].template head<3>().template cast<double>();
        const Eigen::Vector3d target = r.velocity + r.spin.cross(x - r.centre);
        const Eigen::Vector3d nv = v + r.take * (target - v);
        p.v[i].template head<3>() = nv.cast<Real>();
    }
}

template void damp_deformation<float>(ParticlesT<float>&, std::span<const uint32_t>, std::span<const float>, float, std::vector<PieceMoments>&);
template void damp_deformation<double>(ParticlesT<double>&, std::span<const uint32_t>, std::span<const float>, double,
                                       std::vector<PieceMoments>&);

} // namespace pbdsplat::sim
