#include "sim/volume.h"
#include "sim/vec4_ops.h"

#include <algorithm>

namespace pbdsplat::sim {
namespace {
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

void solve_volume(VolumeConstraint& c, Particles& p, Vec4Array& grad, bool xpbd, float stiffness, float alpha_tilde) {
    // Gradient of 6V at vertex i: the sum over its triangles (i, j, k) of x_j x x_k (eq. 9 as a
    // triple product). By Euler's theorem for this degree-3 function, sum x_i . g_i = 18 V, so
    // the volume comes out of the same pass.
    const Vec4f* x = p.x.data();
    const float* w = p.w.data();
    const size_t nv = c.vertices.size();
    double eighteen_v = 0.0, denom = 0.0;
    const bool caps = !c.cap_loops.empty();
    for (size_t n = 0; n < nv; ++n) {
        const uint32_t i = c.vertices[n];
        Vec4f g = Vec4f::Zero();
        for (uint32_t r = c.ring_start[n]; r < c.ring_start[n + 1]; ++r) g += cross3(x[c.ring[r][0]], x[c.ring[r][1]]);
        grad[i] = g;
        if (!caps) {
            eighteen_v += double(x[i].dot(g));
            denom += double(w[i]) * double(g.squaredNorm());
        }
    }
    if (caps) {
        for (const auto& loop : c.cap_loops) {
            Vec4f centroid = Vec4f::Zero();
            for (uint32_t i : loop) centroid += x[i];
            centroid /= float(loop.size());
            Vec4f g_centroid = Vec4f::Zero();
            for (size_t k = 0; k < loop.size(); ++k) {
                const uint32_t ia = loop[k], ib = loop[(k + 1) % loop.size()];
                grad[ia] += cross3(x[ib], centroid);
                grad[ib] += cross3(centroid, x[ia]);
                g_centroid += cross3(x[ia], x[ib]);
            }
            // The centroid moves with every loop vertex (1/n each).
            g_centroid /= float(loop.size());
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
    float scale;
    if (xpbd) {
        const double dlambda = (-C - double(alpha_tilde) * c.lambda) / (denom + double(alpha_tilde));
        c.lambda += float(dlambda);
        scale = float(dlambda / 6.0);
    } else {
        scale = float(-double(stiffness) * C / denom / 6.0);
    }
    Vec4f* xw = p.x.data();
    for (size_t n = 0; n < nv; ++n) {
        const uint32_t i = c.vertices[n];
        xw[i] += (scale * w[i]) * grad[i];
    }
}

} // namespace pbdsplat::sim
