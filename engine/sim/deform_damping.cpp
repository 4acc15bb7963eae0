#include "sim/deform_damping.h"

#include <cmath>


namespace pbdsplat::sim {

namespace {
// A piece's rigid motion: its centre, the centre's velocity and its spin.
struct Rigid {
    Eigen::Vector3d c, v, w;
    double keep_off = 0.0;  // the share of the deviation taken off this substep
};

Rigid rigid_of(const PieceMoments& s, double share) {
    Rigid r{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 0.0};
    if (!(s.m > 0.0)) return r;
    r.c = s.mx / s.m, r.v = s.mv / s.m, r.keep_off = share;
    // About the centre: L = sum m x*v - M c*v_c, I = sum m (|x|^2 1 - x x^T) - M (|c|^2 1 - c c^T).
    const Eigen::Vector3d L = s.mxv - s.m * r.c.cross(r.v);
    const Eigen::Matrix3d xx = s.mxx - s.m * r.c * r.c.transpose();
    const Eigen::Matrix3d I = Eigen::Matrix3d::Identity() * xx.trace() - xx;
    // A piece too thin to spin about some axis (a strand, one particle) keeps no spin: its
    // inertia cannot be inverted safely, and the centre's velocity is the rigid motion there is.
    const double scale = I.trace();
    if (scale > 0.0 && std::abs(I.determinant()) > 1e-9 * scale * scale * scale) r.w = I.ldlt().solve(L);
    return r;
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
    std::vector<Rigid> rigid(pieces);
    for (size_t k = 0; k < pieces; ++k)
        if (rate[k] > 0.0f) rigid[k] = rigid_of(scratch[k], 1.0 - std::exp(-double(rate[k]) * double(h)));
    for (size_t i = 0; i < p.size(); ++i) {
        const uint32_t k = piece[i];
        if (k >= pieces || !(rigid[k].keep_off > 0.0) || !(p.w[i] > Real(0))) continue;
        const Rigid& r = rigid[k];
        const Eigen::Vector3d x = p.x[i].template head<3>().template cast<double>(), v = p.v[i].template head<3>().template cast<double>();
        const Eigen::Vector3d target = r.v + r.w.cross(x - r.c);
        const Eigen::Vector3d nv = v + r.keep_off * (target - v);
        p.v[i].template head<3>() = nv.cast<Real>();
    }
}

template void damp_deformation<float>(ParticlesT<float>&, std::span<const uint32_t>, std::span<const float>, float, std::vector<PieceMoments>&);
template void damp_deformation<double>(ParticlesT<double>&, std::span<const uint32_t>, std::span<const float>, double,
                                       std::vector<PieceMoments>&);

} // namespace pbdsplat::sim
