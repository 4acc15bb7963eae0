#include "sim/volume.h"

#include <algorithm>

#include "sim/vec4_ops.h"

namespace pbdsplat::sim {

template <class Real>
double constraint_volume(const VolumeConstraint& c, const Vec4ArrayT<Real>& x) {
    auto p3 = [&](uint32_t i) -> Vec3d { return x[i].template head<3>().template cast<double>(); };
    double v = 0.0;
    for (const auto& t : c.triangles) v += p3(t[0]).dot(p3(t[1]).cross(p3(t[2])));
    for (const auto& loop : c.cap_loops) {
        Vec3d centroid = Vec3d::Zero();
        for (uint32_t i : loop) centroid += p3(i);
        centroid /= double(loop.size());
        for (size_t k = 0; k < loop.size(); ++k) v += p3(loop[k]).dot(p3(loop[(k + 1) % loop.size()]).cross(centroid));
    }
    return v / 6.0;
}

void build_rings(VolumeConstraint& c) {
    uint32_t max_v = 0;
    for (const auto& t : c.triangles) max_v = std::max({max_v, t[0], t[1], t[2]});
    std::vector<uint32_t> count(size_t(max_v) + 1, 0);
    for (const auto& t : c.triangles)
        for (uint32_t v : t) ++count[v];
    c.vertices.clear();
    c.ring_start.assign(1, 0);
    std::vector<uint32_t> slot(count.size(), 0);
    for (uint32_t v = 0; v < count.size(); ++v) {
        if (!count[v]) continue;
        slot[v] = c.ring_start.back();
        c.vertices.push_back(v);
        c.ring_start.push_back(c.ring_start.back() + count[v]);
    }
    c.ring.assign(c.ring_start.back(), {0, 0});
    for (const auto& t : c.triangles) {
        c.ring[slot[t[0]]++] = {t[1], t[2]};
        c.ring[slot[t[1]]++] = {t[2], t[0]};
        c.ring[slot[t[2]]++] = {t[0], t[1]};
    }
}

template <class Real>
void solve_volume(VolumeConstraint& c, ParticlesT<Real>& p, Vec4ArrayT<Real>& grad, bool xpbd, Real stiffness,
                  Real alpha_tilde) {
    // Gradient of 6V at vertex i: the sum over its triangles (i, j, k) of x_j x x_k (eq. 9 as a
    // triple product). By Euler's theorem for this degree-3 function, sum x_i . g_i = 18 V, so
    // the volume comes out of the same pass.
    const Vec4<Real>* x = p.x.data();
    const Real* w = p.w.data();
    const size_t nv = c.vertices.size();
    double eighteen_v = 0.0, denom = 0.0;
    const bool caps = !c.cap_loops.empty();
    for (size_t n = 0; n < nv; ++n) {
        const uint32_t i = c.vertices[n];
        Vec4<Real> g = Vec4<Real>::Zero();
        for (uint32_t r = c.ring_start[n]; r < c.ring_start[n + 1]; ++r) g += cross3<Real>(x[c.ring[r][0]], x[c.ring[r][1]]);
        grad[i] = g;
        if (!caps) {
            eighteen_v += double(x[i].dot(g));
            denom += double(w[i]) * double(g.squaredNorm());
        }
    }
    if (caps) {
        for (const auto& loop : c.cap_loops) {
            Vec4<Real> centroid = Vec4<Real>::Zero();
            for (uint32_t i : loop) centroid += x[i];
            centroid /= Real(loop.size());
            Vec4<Real> g_centroid = Vec4<Real>::Zero();
            for (size_t k = 0; k < loop.size(); ++k) {
                const uint32_t ia = loop[k], ib = loop[(k + 1) % loop.size()];
                grad[ia] += cross3<Real>(x[ib], centroid);
                grad[ib] += cross3<Real>(centroid, x[ia]);
                g_centroid += cross3<Real>(x[ia], x[ib]);
            }
            // The centroid moves with every loop vertex (1/n each).
            g_centroid /= Real(loop.size());
            for (uint32_t i : loop) grad[i] += g_centroid;
        }
        for (size_t n = 0; n < nv; ++n) {
            const uint32_t i = c.vertices[n];
            eighteen_v += double(x[i].dot(grad[i]));
            denom += double(w[i]) * double(grad[i].squaredNorm());
        }
    }
    const double C = eighteen_v / 18.0 - double(c.pressure) * c.rest_volume;
    denom /= 36.0;  // |grad V|^2 = |grad 6V|^2 / 36
    if (denom < 1e-30) return;
    Real scale;
    if (xpbd) {
        const double dlambda = (-C - double(alpha_tilde) * c.lambda) / (denom + double(alpha_tilde));
        c.lambda += dlambda;
        scale = Real(dlambda / 6.0);
    } else {
        scale = Real(-double(stiffness) * C / denom / 6.0);
    }
    Vec4<Real>* xw = p.x.data();
    for (size_t n = 0; n < nv; ++n) {
        const uint32_t i = c.vertices[n];
        xw[i] += (scale * w[i]) * grad[i];
    }
}

template double constraint_volume<float>(const VolumeConstraint&, const Vec4ArrayT<float>&);
template double constraint_volume<double>(const VolumeConstraint&, const Vec4ArrayT<double>&);
template void solve_volume<float>(VolumeConstraint&, ParticlesT<float>&, Vec4ArrayT<float>&, bool, float, float);
template void solve_volume<double>(VolumeConstraint&, ParticlesT<double>&, Vec4ArrayT<double>&, bool, double, double);

} // namespace pbdsplat::sim
