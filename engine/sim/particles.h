#pragma once
// Per-particle state in compact arrays. Positions, previous positions and velocities are 16-byte
// aligned float4 (w unused, kept 0) so the hot loops run four lanes at a time; inverse masses
// sit in their own array (0 = pinned).
#include <cstdint>
#include <vector>

#include "core/math.h"

namespace pbdsplat::sim {

using Vec4Array = std::vector<Vec4f>;  // C++17 aligned new keeps Eigen's alignment

struct Particles {
    Vec4Array x;       // positions
    Vec4Array x_prev;  // positions at the start of the current (sub)step
    Vec4Array v;       // velocities
    std::vector<float> w;  // inverse masses

    size_t size() const { return x.size(); }
    void resize(size_t n);
    // Total mass of the particles that are not pinned.
    double free_mass() const;
    // Sum of m_i v_i over particles that are not pinned.
    Vec3d linear_momentum() const;
};

inline Vec3f xyz(const Vec4f& p) { return p.head<3>(); }
inline Vec4f to4(const Vec3f& p) { return Vec4f(p.x(), p.y(), p.z(), 0.0f); }

} // namespace pbdsplat::sim
