#include "sim/volume.h"

namespace pbdsplat::sim {
namespace {
inline Vec4f cross4(const Vec4f& a, const Vec4f& b) { return a.cross3(b); }  // w stays 0
} // namespace

double constraint_volume(const VolumeConstraint& c, const Vec4Array& x) {
    double v = 0.0;
    for (const auto& t : c.triangles) {
        const Vec3d a = x[t[0]].head<3>().cast<double>(), b = x[t[1]].head<3>().cast<double>(),
                    d = x[t[2]].head<3>().cast<double>();
        v += a.dot(b.cross(d));
    }
    for (const auto& loop : c.cap_loops) {
        Vec3d centroid = Vec3d::Zero();
        for (uint32_t i : loop) centroid += x[i].head<3>().cast<double>();
        centroid /= double(loop.size());
        for (size_t k = 0; k < loop.size(); ++k) {
            const Vec3d a = x[loop[k]].head<3>().cast<double>(), b = x[loop[(k + 1) % loop.size()]].head<3>().cast<double>();
            v += a.dot(b.cross(centroid));
        }
    }
    return v / 6.0;
}

void solve_volume(VolumeConstraint& c, Particles& p, Vec4Array& grad, bool xpbd, float stiffness, float alpha_tilde) {
    // Gradient of 6V with respect to each corner: the cross product of the other two corners
    // (eq. 9 as a triple product). The volume itself comes from the same cross products.
    double six_v = 0.0;
    for (const auto& t : c.triangles) {
        const Vec4f& a = p.x[t[0]];
        const Vec4f& b = p.x[t[1]];
        const Vec4f& d = p.x[t[2]];
        const Vec4f bd = cross4(b, d);
        grad[t[0]] += bd;
        grad[t[1]] += cross4(d, a);
        grad[t[2]] += cross4(a, b);
        six_v += double(a.dot(bd));
    }
    for (const auto& loop : c.cap_loops) {
        Vec4f centroid = Vec4f::Zero();
        for (uint32_t i : loop) centroid += p.x[i];
        centroid /= float(loop.size());
        Vec4f g_centroid = Vec4f::Zero();
        for (size_t k = 0; k < loop.size(); ++k) {
            const uint32_t ia = loop[k], ib = loop[(k + 1) % loop.size()];
            const Vec4f& a = p.x[ia];
            const Vec4f& b = p.x[ib];
            grad[ia] += cross4(b, centroid);
            grad[ib] += cross4(centroid, a);
            const Vec4f ab = cross4(a, b);
            g_centroid += ab;
            six_v += double(centroid.dot(ab));
        }
        // The centroid moves with every loop vertex (1/n each).
        g_centroid /= float(loop.size());
        for (uint32_t i : loop) grad[i] += g_centroid;
    }
    // Collect the particles touched and the denominator sum w |grad|^2 (in units of 6V).
    const double C = six_v / 6.0 - double(c.pressure) * c.rest_volume;
    double denom = 0.0;
    const size_t n = p.size();
    for (size_t i = 0; i < n; ++i) denom += double(p.w[i]) * double(grad[i].squaredNorm());
    denom /= 36.0;  // grad of V = grad of 6V / 6
    if (denom < 1e-30) {
        for (size_t i = 0; i < n; ++i) grad[i].setZero();
        return;
    }
    float scale;
    if (xpbd) {
        const double dlambda = (-C - double(alpha_tilde) * c.lambda) / (denom + double(alpha_tilde));
        c.lambda += float(dlambda);
        scale = float(dlambda / 6.0);
    } else {
        scale = float(-double(stiffness) * C / denom / 6.0);
    }
    for (size_t i = 0; i < n; ++i) {
        p.x[i] += (scale * p.w[i]) * grad[i];
        grad[i].setZero();
    }
}

} // namespace pbdsplat::sim
