#pragma once
// Per-particle state in compact arrays. Positions, previous positions and velocities are 16-byte
// aligned 4-vectors (w unused, kept 0) so the hot loops run four lanes at a time; inverse masses
// sit in their own array (0 = pinned). The solver runs in float; the accuracy benchmark's
// reference runs the same code in double.
#include <cstdint>
#include <vector>

#include "core/math.h"

namespace pbdsplat::sim {

template <class Real>
using Vec4 = Eigen::Matrix<Real, 4, 1>;
template <class Real>
using Vec4ArrayT = std::vector<Vec4<Real>>;  // C++17 aligned new keeps Eigen's alignment
using Vec4Array = Vec4ArrayT<float>;

template <class Real>
struct ParticlesT {
    Vec4ArrayT<Real> x;       // positions
    Vec4ArrayT<Real> x_prev;  // positions at the start of the current (sub)step
    Vec4ArrayT<Real> v;       // velocities
    std::vector<Real> w;      // inverse masses

    size_t size() const { return x.size(); }
    void resize(size_t n) {
        x.resize(n, Vec4<Real>::Zero());
        x_prev.resize(n, Vec4<Real>::Zero());
        v.resize(n, Vec4<Real>::Zero());
        w.resize(n, Real(0));
    }
    // Sum of m_i v_i over particles that are not pinned.
    Vec3d linear_momentum() const {
        Vec3d p = Vec3d::Zero();
        for (size_t i = 0; i < size(); ++i)
            if (w[i] > Real(0)) p += v[i].template head<3>().template cast<double>() / double(w[i]);
        return p;
    }
};
using Particles = ParticlesT<float>;

template <class Real>
inline Vec3f xyz(const Vec4<Real>& p) { return p.template head<3>().template cast<float>(); }
template <class Real = float>
inline Vec4<Real> to4(const Vec3f& p) { return Vec4<Real>(Real(p.x()), Real(p.y()), Real(p.z()), Real(0)); }

} // namespace pbdsplat::sim
