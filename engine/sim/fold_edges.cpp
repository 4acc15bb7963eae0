#include "sim/fold_edges.h"

#include <algorithm>
#include <cmath>

#include "sim/over_triangle.h"

namespace pbdsplat::sim {
namespace {

// The squared distance between segments (p0, p1) and (q0, q1).
float edge_segment_distance2(const Vec3f& p0, const Vec3f& p1, const Vec3f& q0, const Vec3f& q1) {
    const Vec3f d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
    const float a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
    float s = 0.0f, t = 0.0f;
    if (a <= 0.0f && e <= 0.0f) return r.squaredNorm();
    if (a <= 0.0f) {
        t = std::clamp(f / e, 0.0f, 1.0f);
    } else {
        const float c = d1.dot(r);
        if (e <= 0.0f) {
            s = std::clamp(-c / a, 0.0f, 1.0f);
        } else {
            const float b = d1.dot(d2), denom = a * e - b * b;
            s = denom > 0.0f ? std::clamp((b * f - c * e) / denom, 0.0f, 1.0f) : 0.0f;
            t = (b * s + f) / e;
            if (t < 0.0f) t = 0.0f, s = std::clamp(-c / a, 0.0f, 1.0f);
            else if (t > 1.0f) t = 1.0f, s = std::clamp((b - c) / a, 0.0f, 1.0f);
        }
    }
    return (p0 + s * d1 - (q0 + t * d2)).squaredNorm();
}

// Whether the segments' distance d has on2 <= d^2 < r2, the exact distance taken only where
// their midpoints and lengths leave it open.
bool pair_within(const Vec3f& a, const Vec3f& b, const Vec3f& c, const Vec3f& d, float on2, float r2) {
    const float mid = (0.5f * (a + b - c - d)).norm(), half = 0.5f * ((b - a).norm() + (d - c).norm());
    const float low = std::max(mid - half, 0.0f), high = mid + half;
    if (low * low >= r2 || high * high < on2) return false;
    if (low * low >= on2 && high * high < r2) return true;
    const float d2 = edge_segment_distance2(a, b, c, d);
    return d2 >= on2 && d2 < r2;
}

uint32_t spread_bits(uint32_t x) {  // 10 bits to every third of 30
    x &= 0x3ffu;
    x = (x | (x << 16)) & 0x030000ffu;
    x = (x | (x << 8)) & 0x0300f00fu;
    x = (x | (x << 4)) & 0x030c30c3u;
    return (x | (x << 2)) & 0x09249249u;
}

// Per edge, its place in the order of its rest midpoint's Morton code (ties by index); the
// identity where rest positions are not known.
std::vector<uint32_t> space_order(const std::vector<Vec3f>& rest, const std::vector<std::array<uint32_t, 2>>& edges) {
    std::vector<uint32_t> order(edges.size()), rank(edges.size());
    for (uint32_t e = 0; e < order.size(); ++e) order[e] = rank[e] = e;
    const bool known = std::all_of(edges.begin(), edges.end(), [&](const auto& e) { return e[1] < rest.size(); });
    if (edges.empty() || !known) return rank;
    Eigen::AlignedBox3f box;
    for (const Vec3f& r : rest) box.extend(r);
    const Vec3f scale = (1023.0f / box.sizes().cwiseMax(1e-12f).array()).matrix();
    std::vector<uint32_t> code(edges.size());
    for (size_t e = 0; e < edges.size(); ++e) {
        const Vec3f m = (0.5f * (rest[edges[e][0]] + rest[edges[e][1]]) - box.min()).cwiseProduct(scale);
        code[e] = spread_bits(uint32_t(m.x())) | spread_bits(uint32_t(m.y())) << 1 | spread_bits(uint32_t(m.z())) << 2;
    }
    std::sort(order.begin(), order.end(), [&](uint32_t x, uint32_t y) { return code[x] != code[y] ? code[x] < code[y] : x < y; });
    for (uint32_t k = 0; k < order.size(); ++k) rank[order[k]] = k;
    return rank;
}

bool both_inside(float s, float t) { return s > 0.0f && s < 1.0f && t > 0.0f && t < 1.0f; }

// Edges nearer parallel than this (the sine of their angle) have no normal worth keeping a side
// along: they cannot slice through each other, only slide along.
constexpr float k_sin_min = 0.2f;

} // namespace

bool line_closest_params(const Vec3f& p0, const Vec3f& p1, const Vec3f& q0, const Vec3f& q1, float sin_min, float& s, float& t) {
    const Vec3f d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
    const float a = d1.squaredNorm(), e = d2.squaredNorm(), b = d1.dot(d2);
    const float denom = a * e - b * b;  // |d1 x d2|^2
    if (!(denom > sin_min * sin_min * a * e)) return false;
    const float c = d1.dot(r), f = d2.dot(r);
    s = (b * f - c * e) / denom;
    t = (a * f - b * c) / denom;
    return true;
}

template <class Real>
void FoldEdgesT<Real>::make_edges(const SoftBodyT<Real>& body) {
    const size_t n = body.particle_count();
    std::vector<uint64_t> keys;  // (low corner, high corner, corner slot) packed, sorted
    keys.reserve(body.triangles.size() * 3);
    triangle_edges_.assign(body.triangles.size(), {UINT32_MAX, UINT32_MAX, UINT32_MAX});
    std::vector<std::array<uint32_t, 2>> slot_edge;  // per key: its corners
    for (uint32_t t = 0; t < body.triangles.size(); ++t) {
        const mesh::Triangle& tri = body.triangles[t];
        if (tri[0] >= n || tri[1] >= n || tri[2] >= n || body.piece_of_particle[tri[0]] == k_no_piece) continue;
        for (uint32_t k = 0; k < 3; ++k) {
            const uint32_t u = std::min(tri[k], tri[(k + 1) % 3]), v = std::max(tri[k], tri[(k + 1) % 3]);
            keys.push_back((uint64_t(u) * uint64_t(n) + v) << 2 | k);
            slot_edge.push_back({u, v});
            triangle_edges_[t][k] = uint32_t(keys.size() - 1);  // the key's slot, for now
        }
    }
    std::vector<uint32_t> order(keys.size());
    for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](uint32_t x, uint32_t y) { return keys[x] >> 2 != keys[y] >> 2 ? keys[x] < keys[y] : x < y; });
    std::vector<uint32_t> edge_of_slot(keys.size());
    edges_.clear();
    for (size_t k = 0; k < order.size(); ++k) {
        if (k == 0 || keys[order[k]] >> 2 != keys[order[k - 1]] >> 2) edges_.push_back(slot_edge[order[k]]);
        edge_of_slot[order[k]] = uint32_t(edges_.size() - 1);
    }
    // Edges in space order (by their rest midpoints' Morton codes): a pair's two edges then lie
    // near each other in memory, and the scan reads its spheres from cache.
    const std::vector<uint32_t> rank = space_order(body.rest_positions, edges_);
    std::vector<std::array<uint32_t, 2>> sorted(edges_.size());
    for (size_t e = 0; e < edges_.size(); ++e) sorted[rank[e]] = edges_[e];
    edges_.swap(sorted);
    for (auto& te : triangle_edges_)
        for (uint32_t& e : te)
            if (e != UINT32_MAX) e = rank[edge_of_slot[e]];
}

template <class Real>
void FoldEdgesT<Real>::build(const SoftBodyT<Real>& body, std::span<const uint32_t> start, std::span<const uint32_t> near, float radius, float on) {
    make_edges(body);
    pairs_.clear();
    runs_.clear();
    active_.clear();
    built_ = true;
    const std::vector<Vec3f>& rest = body.rest_positions;
    const size_t n = body.particle_count();
    if (rest.size() != n || start.size() != n + 1 || body.rings.triangles.keys() < n) return;
    stamp_.assign(edges_.size(), UINT32_MAX);
    const float r2 = radius * radius, on2 = on * on;
    for (uint32_t u = 0; u < n; ++u)
        for (const uint32_t t0 : body.rings.triangles.of(u))
            for (const uint32_t e : triangle_edges_[t0]) {
                // Each edge once, from its lower corner, against the edges of that corner's
                // neighbourhood.
                if (e == UINT32_MAX || edges_[e][0] != u || stamp_[e] == e) continue;
                stamp_[e] = e;
                const auto [a, b] = edges_[e];
                const uint32_t begin = uint32_t(pairs_.size());
                for (uint32_t k = start[u]; k < start[u + 1]; ++k)
                    for (const uint32_t f : triangle_edges_[near[k]]) {
                        if (f == UINT32_MAX || f <= e || stamp_[f] == e) continue;
                        stamp_[f] = e;
                        const auto [c, d] = edges_[f];
                        bool shared = false;
                        for (const uint32_t x : {a, b})
                            for (const uint32_t y : {c, d}) shared = shared || x == y || rest[x] == rest[y];
                        if (shared) continue;
                        if (pair_within(rest[a], rest[b], rest[c], rest[d], on2, r2)) pairs_.push_back(f);
                    }
                if (pairs_.size() > begin) runs_.push_back({e, begin, uint32_t(pairs_.size())});
            }
    // In the edges' space order, so that the scan reads its spheres from cache.
    std::sort(runs_.begin(), runs_.end(), [](const Run& x, const Run& y) { return x.edge < y.edge; });
}

template <class Real>
void FoldEdgesT<Real>::find(const SoftBodyT<Real>& body, std::span<const uint8_t> folded, float thickness, float reach) {
    active_.clear();
    thickness_ = thickness, reach_ = reach;
    const ParticlesT<Real>& p = body.particles;
    if (folded.size() != body.particle_count()) return;
    spheres_.resize(edges_.size());
    for (size_t e = 0; e < edges_.size(); ++e) {
        const Vec3f a = pos3(p.x[edges_[e][0]]), b = pos3(p.x[edges_[e][1]]);
        const Vec3f m = 0.5f * (a + b);
        spheres_[e] = Vec4f(m.x(), m.y(), m.z(), 0.5f * (b - a).norm());
    }
    // Edges in contiguous chunks, one list each, joined in chunk order: the candidates and their
    // order are one thread's for any thread count.
    const unsigned chunks = pool_ && pool_->size() > 1 && runs_.size() >= k_edges_per_chunk * pool_->chunks() ? pool_->chunks() : 1u;
    chunk_.resize(chunks);
    const auto run = [&](unsigned chunk, size_t begin, size_t end) {
        chunk_[chunk].clear();
        scan(p, folded, begin, end, chunk_[chunk]);
    };
    if (chunks > 1) pool_->parallel_for(runs_.size(), run);
    else run(0, 0, runs_.size());
    if (chunks == 1) return active_.swap(chunk_[0]);
    for (const std::vector<Candidate>& c : chunk_) active_.insert(active_.end(), c.begin(), c.end());
}

template <class Real>
void FoldEdgesT<Real>::scan(const ParticlesT<Real>& p, std::span<const uint8_t> folded, size_t first, size_t last, std::vector<Candidate>& out) const {
    for (size_t r = first; r < last; ++r) {
        const Run& run = runs_[r];
        const auto [a, b] = edges_[run.edge];
        if (!folded[a] && !folded[b]) continue;
        const Vec4f& se = spheres_[run.edge];
        for (uint32_t k = run.begin; k < run.end; ++k) test(p, a, b, se, pairs_[k], out);
    }
}

template <class Real>
void FoldEdgesT<Real>::test(const ParticlesT<Real>& p, uint32_t a, uint32_t b, const Vec4f& se, uint32_t f, std::vector<Candidate>& out) const {
    const Vec4f& sf = spheres_[f];
    const float r = se.w() + sf.w() + reach_;
    if ((se.head<3>() - sf.head<3>()).squaredNorm() > r * r) return;
    const auto [c, d] = edges_[f];
    if (!(p.w[a] > Real(0) || p.w[b] > Real(0) || p.w[c] > Real(0) || p.w[d] > Real(0))) return;
    // Beside each other as predicted (their lines meet off an end, as two edges of a smooth
    // surface do), they cannot cross this substep: the projection would pass them by.
    const Vec3f xa = pos3(p.x[a]), xb = pos3(p.x[b]), xc = pos3(p.x[c]), xd = pos3(p.x[d]);
    float s, t;
    if (!line_closest_params(xa, xb, xc, xd, k_sin_min, s, t) || !both_inside(s, t)) return;
    // The side is known only where the two overlapped, seen along their normal, when the
    // substep began: beside each other then, one may have come round the other's end.
    const Vec3f a0 = pos3(p.x_prev[a]), b0 = pos3(p.x_prev[b]), c0 = pos3(p.x_prev[c]), d0 = pos3(p.x_prev[d]);
    float s0, t0;
    if (!line_closest_params(a0, b0, c0, d0, k_sin_min, s0, t0) || !both_inside(s0, t0)) return;
    Vec3f n0 = (b0 - a0).cross(d0 - c0).normalized();
    if (n0.dot(c0 + t0 * (d0 - c0) - a0 - s0 * (b0 - a0)) < 0.0f) n0 = -n0;
    Vec3f nn = (xb - xa).cross(xd - xc).normalized();
    if (nn.dot(n0) < 0.0f) nn = -nn;
    if (nn.dot(xc + t * (xd - xc) - xa - s * (xb - xa)) > reach_) return;  // clear of it, on its side
    out.push_back({a, b, c, d, n0});
}

template <class Real>
void FoldEdgesT<Real>::project(ParticlesT<Real>& p) const {
    for (const Candidate& ct : active_) {
        const Vec3f xa = pos3(p.x[ct.a]), xb = pos3(p.x[ct.b]), xc = pos3(p.x[ct.c]), xd = pos3(p.x[ct.d]);
        float s, t;
        // Slid apart (their closest points off an end): a corner over a triangle is the fold
        // guard's, and beside both they no longer cross.
        if (!line_closest_params(xa, xb, xc, xd, k_sin_min, s, t) || !both_inside(s, t)) continue;
        Vec3f nn = (xb - xa).cross(xd - xc).normalized();
        if (nn.dot(ct.n0) < 0.0f) nn = -nn;
        const Real C = Real(nn.dot(xc + t * (xd - xc) - xa - s * (xb - xa))) - Real(thickness_);
        if (C >= Real(0)) continue;
        // Far through already: it came there some other way (see the fold guard).
        if (C < -Real(reach_)) continue;
        const Real ua = Real(1.0f - s), ub = Real(s), uc = Real(1.0f - t), ud = Real(t);
        const Real denom = ua * ua * p.w[ct.a] + ub * ub * p.w[ct.b] + uc * uc * p.w[ct.c] + ud * ud * p.w[ct.d];
        if (!(denom > Real(0))) continue;
        const Vec4<Real> dn = (-C / denom) * to4<Real>(nn);
        p.x[ct.a] -= p.w[ct.a] * ua * dn;
        p.x[ct.b] -= p.w[ct.b] * ub * dn;
        p.x[ct.c] += p.w[ct.c] * uc * dn;
        p.x[ct.d] += p.w[ct.d] * ud * dn;
    }
}

template class FoldEdgesT<float>;
template class FoldEdgesT<double>;

} // namespace pbdsplat::sim
