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

namespace {
// Counting arrays as long as the body: linear, best for a constraint over most of the body.
void build_rings_dense(VolumeConstraint& c, uint32_t max_v) {
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

// Sorting: costs the constraint's own size only, for the many small pieces of a cut body.
void build_rings_sparse(VolumeConstraint& c) {
    c.vertices.clear();
    for (const auto& t : c.triangles) c.vertices.insert(c.vertices.end(), t.begin(), t.end());
    std::sort(c.vertices.begin(), c.vertices.end());
    c.ring_start.assign(1, 0);
    size_t unique = 0;
    for (size_t k = 0; k < c.vertices.size();) {
        size_t e = k;
        while (e < c.vertices.size() && c.vertices[e] == c.vertices[k]) ++e;
        c.vertices[unique++] = c.vertices[k];
        c.ring_start.push_back(c.ring_start.back() + uint32_t(e - k));
        k = e;
    }
    c.vertices.resize(unique);
    std::vector<uint32_t> slot(c.ring_start.begin(), c.ring_start.end() - 1);
    auto index = [&](uint32_t v) { return size_t(std::lower_bound(c.vertices.begin(), c.vertices.end(), v) - c.vertices.begin()); };
    c.ring.assign(c.ring_start.back(), {0, 0});
    for (const auto& t : c.triangles) {
        c.ring[slot[index(t[0])]++] = {t[1], t[2]};
        c.ring[slot[index(t[1])]++] = {t[2], t[0]};
        c.ring[slot[index(t[2])]++] = {t[0], t[1]};
    }
}
} // namespace

void build_rings(VolumeConstraint& c) {
    // Either way the vertices come out in increasing order (memory order for the gather).
    uint32_t max_v = 0;
    for (const auto& t : c.triangles) max_v = std::max({max_v, t[0], t[1], t[2]});
    if (c.triangles.size() * 16 >= size_t(max_v)) build_rings_dense(c, max_v);
    else build_rings_sparse(c);
}

size_t volume_blocks(const VolumeConstraint& c) { return (c.vertices.size() + k_volume_block - 1) / k_volume_block; }

template <class Real>
VolumeSums volume_gather(const VolumeConstraint& c, const ParticlesT<Real>& p, Vec4ArrayT<Real>& grad, size_t b) {
    // Gradient of 6V at vertex i: the sum over its triangles (i, j, k) of x_j x x_k (eq. 9 as a
    // triple product).
    const Vec4<Real>* x = p.x.data();
    const Real* w = p.w.data();
    const bool caps = !c.cap_loops.empty();
    VolumeSums s;
    const size_t end = std::min(c.vertices.size(), (b + 1) * k_volume_block);
    for (size_t n = b * k_volume_block; n < end; ++n) {
        const uint32_t i = c.vertices[n];
        Vec4<Real> g = Vec4<Real>::Zero();
        for (uint32_t r = c.ring_start[n]; r < c.ring_start[n + 1]; ++r) g += cross3<Real>(x[c.ring[r][0]], x[c.ring[r][1]]);
        grad[i] = g;
        if (!caps) {
            s.eighteen_v += double(x[i].dot(g));
            s.denom += double(w[i]) * double(g.squaredNorm());
        }
    }
    return s;
}

template <class Real>
void volume_caps(const VolumeConstraint& c, const ParticlesT<Real>& p, Vec4ArrayT<Real>& grad,
                 std::vector<VolumeSums>& block_sums) {
    if (c.cap_loops.empty()) return;
    const Vec4<Real>* x = p.x.data();
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
    // The gradients are complete only now: the sums are taken here, block by block.
    for (size_t b = 0; b < block_sums.size(); ++b) {
        VolumeSums s;
        const size_t end = std::min(c.vertices.size(), (b + 1) * k_volume_block);
        for (size_t n = b * k_volume_block; n < end; ++n) {
            const uint32_t i = c.vertices[n];
            s.eighteen_v += double(x[i].dot(grad[i]));
            s.denom += double(p.w[i]) * double(grad[i].squaredNorm());
        }
        block_sums[b] = s;
    }
}

template <class Real>
Real volume_step(VolumeConstraint& c, const std::vector<VolumeSums>& block_sums, bool xpbd, Real stiffness,
                 Real alpha_tilde) {
    VolumeSums total;
    for (const VolumeSums& s : block_sums) total.eighteen_v += s.eighteen_v, total.denom += s.denom;
    const double C = total.eighteen_v / 18.0 - double(c.pressure) * c.rest_volume;
    const double denom = total.denom / 36.0;  // |grad V|^2 = |grad 6V|^2 / 36
    if (denom < 1e-30) return Real(0);
    if (xpbd) {
        const double dlambda = (-C - double(alpha_tilde) * c.lambda) / (denom + double(alpha_tilde));
        c.lambda += dlambda;
        return Real(dlambda / 6.0);
    }
    return Real(-double(stiffness) * C / denom / 6.0);
}

template <class Real>
void volume_apply(const VolumeConstraint& c, ParticlesT<Real>& p, const Vec4ArrayT<Real>& grad, Real step, size_t b) {
    const size_t end = std::min(c.vertices.size(), (b + 1) * k_volume_block);
    for (size_t n = b * k_volume_block; n < end; ++n) {
        const uint32_t i = c.vertices[n];
        p.x[i] += (step * p.w[i]) * grad[i];
    }
}

template <class Real>
void solve_volume(VolumeConstraint& c, ParticlesT<Real>& p, Vec4ArrayT<Real>& grad, bool xpbd, Real stiffness,
                  Real alpha_tilde) {
    std::vector<VolumeSums> sums(volume_blocks(c));
    for (size_t b = 0; b < sums.size(); ++b) sums[b] = volume_gather<Real>(c, p, grad, b);
    volume_caps<Real>(c, p, grad, sums);
    const Real step = volume_step<Real>(c, sums, xpbd, stiffness, alpha_tilde);
    for (size_t b = 0; b < sums.size(); ++b) volume_apply<Real>(c, p, grad, step, b);
}

#define PBDSPLAT_INSTANTIATE(Real)                                                                               \
    template double constraint_volume<Real>(const VolumeConstraint&, const Vec4ArrayT<Real>&);                \
    template VolumeSums volume_gather<Real>(const VolumeConstraint&, const ParticlesT<Real>&, Vec4ArrayT<Real>&, \
                                            size_t);                                                           \
    template void volume_caps<Real>(const VolumeConstraint&, const ParticlesT<Real>&, Vec4ArrayT<Real>&,         \
                                    std::vector<VolumeSums>&);                                                 \
    template Real volume_step<Real>(VolumeConstraint&, const std::vector<VolumeSums>&, bool, Real, Real);        \
    template void volume_apply<Real>(const VolumeConstraint&, ParticlesT<Real>&, const Vec4ArrayT<Real>&, Real,  \
                                     size_t);                                                                  \
    template void solve_volume<Real>(VolumeConstraint&, ParticlesT<Real>&, Vec4ArrayT<Real>&, bool, Real, Real);
PBDSPLAT_INSTANTIATE(float)
PBDSPLAT_INSTANTIATE(double)
#undef PBDSPLAT_INSTANTIATE

} // namespace pbdsplat::sim
