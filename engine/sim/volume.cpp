#include "sim/volume.h"

#include <algorithm>

#include <Eigen/Eigenvalues>

#include "sim/vec4_ops.h"

namespace pbdsplat::sim {

template <class Real>
double triangles_six_volume(std::span<const mesh::Triangle> triangles, std::span<const uint32_t> piece_of_particle, uint32_t piece,
                            const Vec4ArrayT<Real>& x) {
    auto p3 = [&](uint32_t i) -> Vec3d { return x[i].template head<3>().template cast<double>(); };
    double v = 0.0;
    for (const mesh::Triangle& t : triangles)
        if (piece_of_particle[t[0]] == piece) v += p3(t[0]).dot(p3(t[1]).cross(p3(t[2])));
    return v;
}

template <class Real>
double cap_six_volume(std::span<const uint32_t> loop, const Vec4ArrayT<Real>& x) {
    auto p3 = [&](uint32_t i) -> Vec3d { return x[i].template head<3>().template cast<double>(); };
    if (loop.empty()) return 0.0;
    Vec3d centroid = Vec3d::Zero();
    for (uint32_t i : loop) centroid += p3(i);
    centroid /= double(loop.size());
    double v = 0.0;
    for (size_t k = 0; k < loop.size(); ++k) v += p3(loop[k]).dot(p3(loop[(k + 1) % loop.size()]).cross(centroid));
    return v;
}

template <class Real>
double caps_six_volume(const std::vector<std::vector<uint32_t>>& loops, const Vec4ArrayT<Real>& x) {
    double v = 0.0;
    for (const auto& loop : loops) v += cap_six_volume<Real>(loop, x);
    return v;
}

template <class Real>
float leak_rate(const VolumeConstraint& c, const Vec4ArrayT<Real>& x) {
    if (!(c.leak > 0.0f) || !(c.rest_volume > 0.0)) return 0.0f;
    const auto position = [&](uint32_t i) -> Vec3d { return x[i].template head<3>().template cast<double>(); };
    double area = 0.0;
    for (const auto& loop : c.cap_loops)
        if (c.is_opening(loop)) area += loop_area(loop, position);
    const double share = area / (k_open_area * std::cbrt(c.rest_volume * c.rest_volume));
    return c.leak * float(std::min(1.0, share));
}

template <class Real>
VolumeWeights volume_weights(std::span<const Real> w, std::span<const float> rest_area) {
    double mass = 0.0, fans = 0.0;
    size_t moving = 0;
    const bool areas = rest_area.size() == w.size();
    for (size_t i = 0; i < w.size(); ++i)
        if (w[i] > Real(0)) mass += 1.0 / double(w[i]), ++moving, fans += areas ? double(rest_area[i]) : 0.0;
    VolumeWeights out;
    if (moving) out.w_most = float(double(k_volume_lightest) * double(moving) / mass);
    if (fans > 0.0) out.skin_density = float(mass / (fans / 6.0));
    return out;
}

size_t volume_blocks(size_t particles) { return (particles + k_volume_block - 1) / k_volume_block; }

namespace {
// A moving particle's terms of VolumeSums::push and turn: (f - 1) g and its moment, for a move
// scaled by f = moved / w; `sign` -1 takes them out again.
template <class Real>
void add_unpaid(VolumeSums& sums, double sign, Real w, Real moved, const Vec4<Real>& x, const Vec4<Real>& g) {
    if (moved == w) return;
    const Vec3d unpaid = (sign * (double(moved) / double(w) - 1.0)) * xyz(g).template cast<double>();
    sums.push += unpaid, sums.turn += xyz(x).template cast<double>().cross(unpaid);
}
} // namespace

template <class Real>
void volume_gather(const VolumeLayout& l, const ParticlesT<Real>& p, Vec4ArrayT<Real>& grad, size_t b, BlockSums& sums) {
    // Gradient of 6V at particle i: the sum over its triangles (i, j, k) of x_j x x_k (eq. 9 as a
    // triple product). The caps' terms come later (volume_caps corrects the sums for them).
    const Vec4<Real>* x = p.x.data();
    const Real* w = p.w.data();
    sums.clear();
    // The running sums stay in registers while neighbours share a slot (they mostly do) and go
    // back to the block's entry when the slot changes: summed through memory, each particle
    // waited for the previous one's store (a fifth of the gather's time at 41k particles). The
    // additions happen in the same order as before, so the sums are the same to the bit.
    uint32_t slot = k_no_volume;
    size_t at = 0;
    VolumeSums run;
    auto switch_to = [&](uint32_t next) {
        if (slot != k_no_volume) sums[at].second = run;
        at = 0;
        while (at < sums.size() && sums[at].first != next) ++at;
        if (at == sums.size()) sums.push_back({next, VolumeSums{}});
        slot = next, run = sums[at].second;
    };
    const size_t end = std::min(p.size(), (b + 1) * k_volume_block);
    for (size_t i = b * k_volume_block; i < end; ++i) {
        const uint32_t s = l.slot_of(uint32_t(i));
        if (s == k_no_volume) continue;
        if (s != slot) switch_to(s);
        const auto ring = l.ring->of(uint32_t(i));
        const Vec4<Real> g = sum_of_cross3<Real>(ring, [x](uint32_t k) -> const Vec4<Real>& { return x[k]; });
        grad[i] = g;
        run.eighteen_v += double(x[i].dot(g));
        float share = 1.0f;
        if (!l.share.empty()) {
            // The fan's own vector area: g, less for an open fan what it owes to where the origin is.
            Vec4<Real> fan = g;
            if (l.open_fan[i]) {
                Vec4<Real> open = Vec4<Real>::Zero();
                for (const auto& r : ring) open += x[r[1]] - x[r[0]];
                fan -= cross3<Real>(x[i], open);
            }
            l.share[i] = share = push_share<Real>(l.rest_area[i], fan);
        }
        const Real moved = l.weight(w[i]) * Real(share);
        run.denom += double(moved) * double(g.squaredNorm());
        if (w[i] > Real(0)) add_unpaid<Real>(run, 1.0, w[i], moved, x[i], g);
    }
    if (slot != k_no_volume) sums[at].second = run;
}

template <class Real>
void volume_moments(const VolumeLayout& l, const ParticlesT<Real>& p, std::span<const uint8_t> wanted, size_t b, BlockMoments& out) {
    out.clear();
    uint32_t slot = k_no_volume;
    MassMoments* m = nullptr;
    const size_t end = std::min(p.size(), (b + 1) * k_volume_block);
    for (size_t i = b * k_volume_block; i < end; ++i) {
        const uint32_t s = l.slot_of(uint32_t(i));
        if (s == k_no_volume || !wanted[s] || !(p.w[i] > Real(0))) continue;
        if (s != slot) {
            auto it = std::find_if(out.begin(), out.end(), [s](const auto& e) { return e.first == s; });
            if (it == out.end()) it = out.insert(out.end(), {s, MassMoments{}});
            slot = s, m = &it->second;
        }
        const double mi = 1.0 / double(p.w[i]);
        const Vec3d at = xyz(p.x[i]).template cast<double>();
        m->mass += mi, m->first += mi * at, m->second.noalias() += (mi * at) * at.transpose();
    }
}


namespace {
// Scales the loop particles' push_share by their own weight over their weight with the cap's mass
// (VolumeWeights) added: moved by 1 / (m_i + cap share) instead of 1 / m_i.
template <class Real>
void weigh_cap(const VolumeLayout& l, std::span<const uint32_t> loop, const ParticlesT<Real>& p, const Vec4<Real>& centroid) {
    if (l.share.empty() || !(l.skin_density > 0.0f)) return;
    const size_t n = loop.size();
    const Vec4<Real>* x = p.x.data();
    // Twice the area cap triangle k, (loop[k], loop[k+1], centroid), has as it lies now.
    Real whole = Real(0);
    const auto doubled = [&](size_t k) { return cross3<Real>(x[loop[k]] - centroid, x[loop[(k + 1) % n]] - centroid).norm(); };
    for (size_t k = 0; k < n; ++k) whole += doubled(k);
    const Real per_doubled = Real(l.skin_density) / Real(6);  // a third of half the doubled area
    Real before = doubled(n - 1);
    for (size_t k = 0; k < n; ++k) {
        const Real after = doubled(k), w = p.w[loop[k]];
        if (w > Real(0)) {
            const Real cap_mass = per_doubled * (before + after + whole / Real(n));
            l.share[loop[k]] *= float(Real(1) / (Real(1) + cap_mass * l.weight(w)));
        }
        before = after;
    }
}
} // namespace

template <class Real>
void volume_caps(const VolumeLayout& l, const VolumeConstraint& c, const ParticlesT<Real>& p, Vec4ArrayT<Real>& grad, VolumeSums& sums) {
    if (c.cap_loops.empty()) return;
    const Vec4<Real>* x = p.x.data();
    // The loop particles' sums were taken without the caps: take them out, add the caps' terms,
    // and put them back. A particle lies once on the loops at most (vertex splitting leaves no
    // bow-tie; topology::check_invariants holds the body to it), so the loops are walked as
    // they are: this runs every iteration, and sorting the loops here cost a body cut 2,000
    // times an eighth of its solver time.
    auto add_sums = [&](double sign) {
        for (const auto& loop : c.cap_loops)
            for (uint32_t i : loop) {
                const Real w = p.w[i], moved = l.weight(w) * Real(l.share_of(i));
                sums.eighteen_v += sign * double(x[i].dot(grad[i]));
                sums.denom += sign * double(moved) * double(grad[i].squaredNorm());
                if (w > Real(0)) add_unpaid<Real>(sums, sign, w, moved, x[i], grad[i]);
            }
    };
    add_sums(-1.0);
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
        // Only the model's own holes: a cut face or a rip weighing as skin left its rim all but
        // still in the pass, and the rest of the piece took the error (bunny_cut's stack sank
        // to 0.58 of its height, default's deflated halves turned inside out).
        if (!c.is_opening(loop)) weigh_cap<Real>(l, loop, p, centroid);
    }
    add_sums(1.0);
}

template <class Real>
Real volume_step(VolumeConstraint& c, const VolumeSums& total, bool xpbd, Real stiffness, Real alpha_tilde) {
    // At most half the volume there is, per projection: a linear step toward a target far off (a
    // pressure factor of 100 set at once) moved every particle tens of radii along its normal
    // in one go, and the skin turned inside out. Ramps of pressure stay well inside this.
    const double volume = total.eighteen_v / 18.0, reach = k_volume_reach * std::abs(volume);
    const double C = std::clamp(volume - double(c.pressure) * c.rest_volume, -reach, reach);
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
RigidNudge<Real> volume_nudge(const VolumeSums& total, const MassMoments& m, Real step) {
    RigidNudge<Real> n;
    if (!total.unbalanced() || !(m.mass > 0.0)) return n;
    auto to4 = [](const Vec3d& v) { return Vec4<Real>(Real(v.x()), Real(v.y()), Real(v.z()), Real(0)); };
    const Vec3d centre = m.first / m.mass;
    n.shift = to4((-double(step) / m.mass) * total.push), n.centre = to4(centre), n.moves = true;
    // The shift moves no moment about the centre; what the impulses turn about it is
    // turn - centre x push, and a turn by a (small) angle a gives the piece I a of it.
    const Eigen::Matrix3d spread = m.second - m.mass * centre * centre.transpose();  // sum m r r^T
    const Eigen::Matrix3d inertia = spread.trace() * Eigen::Matrix3d::Identity() - spread;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(inertia);
    if (eig.info() != Eigen::Success || !(eig.eigenvalues().minCoeff() > 1e-9 * eig.eigenvalues().maxCoeff())) return n;
    const Vec3d moment = double(step) * (total.turn - centre.cross(total.push));
    n.turn = to4(-(eig.eigenvectors() * eig.eigenvalues().cwiseInverse().asDiagonal() * eig.eigenvectors().transpose() * moment));
    return n;
}

template <class Real>
void volume_apply(const VolumeLayout& l, ParticlesT<Real>& p, const Vec4ArrayT<Real>& grad, std::span<const Real> steps,
                  std::span<const RigidNudge<Real>> nudges, size_t b) {
    const size_t end = std::min(p.size(), (b + 1) * k_volume_block);
    for (size_t i = b * k_volume_block; i < end; ++i) {
        const uint32_t s = l.slot_of(uint32_t(i));
        if (s == k_no_volume || !(p.w[i] > Real(0))) continue;
        p.x[i] += (steps[s] * l.weight(p.w[i]) * Real(l.share_of(uint32_t(i)))) * grad[i] + nudges[s].at(p.x[i]);
    }
}

template <class Real>
void solve_volumes(std::span<VolumeConstraint* const> slot_constraints, const VolumeLayout& l, ParticlesT<Real>& p,
                   Vec4ArrayT<Real>& scratch, bool xpbd, Real stiffness, Real inv_h2) {
    const size_t blocks = volume_blocks(p.size()), slots = slot_constraints.size();
    std::vector<BlockSums> sums(blocks);
    for (size_t b = 0; b < blocks; ++b) volume_gather<Real>(l, p, scratch, b, sums[b]);
    std::vector<VolumeSums> totals(slots);
    reduce_blocks<VolumeSums>(sums, totals);
    std::vector<Real> steps(slots);
    std::vector<uint8_t> unbalanced(slots, 0);
    for (size_t s = 0; s < slots; ++s) {
        VolumeSums caps;
        slot_constraints[s]->measured_six_v = totals[s].eighteen_v / 3.0;
        volume_caps<Real>(l, *slot_constraints[s], p, scratch, caps);
        slot_constraints[s]->measured_caps_six_v = caps.eighteen_v / 3.0;
        totals[s].add(caps);
        steps[s] = volume_step<Real>(*slot_constraints[s], totals[s], xpbd, stiffness, Real(slot_constraints[s]->compliance) * inv_h2);
        unbalanced[s] = totals[s].unbalanced();
    }
    std::vector<BlockMoments> block_moments(blocks);
    for (size_t b = 0; b < blocks; ++b) volume_moments<Real>(l, p, unbalanced, b, block_moments[b]);
    std::vector<MassMoments> moments(slots);
    reduce_blocks<MassMoments>(block_moments, moments);
    std::vector<RigidNudge<Real>> nudges(slots);
    for (size_t s = 0; s < slots; ++s) nudges[s] = volume_nudge<Real>(totals[s], moments[s], steps[s]);
    for (size_t b = 0; b < blocks; ++b) volume_apply<Real>(l, p, scratch, steps, nudges, b);
}

#define PBDSPLAT_INSTANTIATE(Real)                                                                                          \
    template double triangles_six_volume<Real>(std::span<const mesh::Triangle>, std::span<const uint32_t>, uint32_t,         \
                                               const Vec4ArrayT<Real>&);                                                    \
    template double cap_six_volume<Real>(std::span<const uint32_t>, const Vec4ArrayT<Real>&);                                \
    template VolumeWeights volume_weights<Real>(std::span<const Real>, std::span<const float>);                                                       \
    template float leak_rate<Real>(const VolumeConstraint&, const Vec4ArrayT<Real>&);                                \
    template double caps_six_volume<Real>(const std::vector<std::vector<uint32_t>>&, const Vec4ArrayT<Real>&);               \
    template void volume_moments<Real>(const VolumeLayout&, const ParticlesT<Real>&, std::span<const uint8_t>, size_t,          \
                                       BlockMoments&);                                                                      \
    template void volume_gather<Real>(const VolumeLayout&, const ParticlesT<Real>&, Vec4ArrayT<Real>&, size_t, BlockSums&);  \
    template void volume_caps<Real>(const VolumeLayout&, const VolumeConstraint&, const ParticlesT<Real>&, Vec4ArrayT<Real>&,  \
                                    VolumeSums&);                                                                            \
    template Real volume_step<Real>(VolumeConstraint&, const VolumeSums&, bool, Real, Real);                                 \
    template RigidNudge<Real> volume_nudge<Real>(const VolumeSums&, const MassMoments&, Real);                                                 \
    template void volume_apply<Real>(const VolumeLayout&, ParticlesT<Real>&, const Vec4ArrayT<Real>&, std::span<const Real>, \
                                     std::span<const RigidNudge<Real>>, size_t);                                                 \
    template void solve_volumes<Real>(std::span<VolumeConstraint* const>, const VolumeLayout&, ParticlesT<Real>&,           \
                                      Vec4ArrayT<Real>&, bool, Real, Real);
PBDSPLAT_INSTANTIATE(float)
PBDSPLAT_INSTANTIATE(double)
#undef PBDSPLAT_INSTANTIATE

} // namespace pbdsplat::sim
