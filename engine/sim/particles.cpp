#include "sim/particles.h"

namespace pbdsplat::sim {

void Particles::resize(size_t n) {
    x.resize(n, Vec4f::Zero());
    x_prev.resize(n, Vec4f::Zero());
    v.resize(n, Vec4f::Zero());
    w.resize(n, 0.0f);
}

double Particles::free_mass() const {
    double m = 0.0;
    for (float wi : w)
        if (wi > 0.0f) m += 1.0 / double(wi);
    return m;
}

Vec3d Particles::linear_momentum() const {
    Vec3d p = Vec3d::Zero();
    for (size_t i = 0; i < size(); ++i)
        if (w[i] > 0.0f) p += v[i].head<3>().cast<double>() / double(w[i]);
    return p;
}

} // namespace pbdsplat::sim
