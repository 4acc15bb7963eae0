#include "sim/fold_guard.h"

#include <algorithm>
#include <cmath>

#include "sim/over_triangle.h"

namespace pbdsplat::sim {
namespace {

// A neighbourhood folded over itself turns some triangle of it past a right angle from the
// particle's normal (two layers meeting face each other); this much short of it already counts.
constexpr float k_folded = 0.25f;

// How far apart at rest (over the mean edge) two edges may lie and still be held apart: a
// crease's two sides within this of each other. Nearly all that the whole neighbourhood gave
// (docs/BENCHMARKS.md, "Surfaces through each other") for a third of its pairs.
constexpr float k_edge_radius = 1.5f;

bool live(const mesh::Triangle& t, size_t n, const std::vector<uint32_t>& piece_of) {
    return t[0] < n && t[1] < n && t[2] < n && piece_of[t[0]] != k_no_piece;
}

} // namespace

template <class Real>
bool FoldGuardT<Real>::stale(const SoftBodyT<Real>& body, const ContactSettings& s) const {
    return body.particle_count() != built_particles_ || body.triangles.size() != built_triangles_ || body.pieces != built_pieces_ ||
           s.thickness != settings_thickness_ || start_.size() != body.particle_count() + 1;
}

template <class Real>
void FoldGuardT<Real>::gather(const SoftBodyT<Real>& body, uint32_t i, float radius, std::vector<uint32_t>& out) {
    // Outward from i through the triangles' corners, as far as `radius` at rest: its rest
    // neighbourhood on its own piece (a slit's other side, at the same rest place, left out).
    const std::vector<Vec3f>& rest = body.rest_positions;
    const size_t n = body.particle_count();
    const float r2 = radius * radius;
    const Vec3f& ri = rest[i];
    queue_.clear();
    queue_.push_back(i);
    vertex_stamp_[i] = i;
    for (size_t q = 0; q < queue_.size(); ++q) {
        for (const uint32_t t : body.rings.triangles.of(queue_[q])) {
            if (triangle_stamp_[t] == i) continue;
            triangle_stamp_[t] = i;
            const mesh::Triangle& tri = body.triangles[t];
            if (!live(tri, n, body.piece_of_particle)) continue;
            bool own = false;
            for (const uint32_t k : tri) {
                own = own || k == i || rest[k] == ri;
                if (vertex_stamp_[k] != i && (rest[k] - ri).squaredNorm() < r2) vertex_stamp_[k] = i, queue_.push_back(k);
            }
            if (own) continue;
            const Vec3f& a = rest[tri[0]];
            const Vec3f& b = rest[tri[1]];
            const Vec3f& c = rest[tri[2]];
            const Over o = over_triangle(ri, a, b, c, unit_normal(a, b, c));
            if (o.height * o.height + o.lateral * o.lateral >= r2) continue;
            // On the triangle at rest (a flat face's vertex over a sliver beside it): one surface
            // with it, on no side of it.
            if (o.lateral <= on_ && std::abs(o.height) <= on_) continue;
            out.push_back(t);
        }
    }
}

template <class Real>
void FoldGuardT<Real>::build(const SoftBodyT<Real>& body, const ContactSettings& s) {
    scale_ = contact_scale(mean_rest_edge(body), s);
    // As far as a candidate may be from a triangle (the gap and the search's slack).
    on_ = k_fold_thickness * scale_.edge + scale_.slack;
    settings_thickness_ = s.thickness;
    rebuild(body);
}

template <class Real>
void FoldGuardT<Real>::rebuild(const SoftBodyT<Real>& body) {
    const size_t n = body.particle_count();
    start_.assign(n + 1, 0);
    near_.clear();
    vertex_stamp_.assign(n, UINT32_MAX);
    triangle_stamp_.assign(body.triangles.size(), UINT32_MAX);
    const bool known = body.rest_positions.size() == n && body.rings.triangles.keys() >= n;
    for (uint32_t i = 0; i < n; ++i) {
        start_[i] = uint32_t(near_.size());
        if (known && body.piece_of_particle[i] != k_no_piece) gather(body, i, scale_.exclusion, near_);
    }
    start_[n] = uint32_t(near_.size());
    built_particles_ = n, built_triangles_ = body.triangles.size(), built_pieces_ = body.pieces;
    built_triangles_list_ = body.triangles;
    build_edges(body);
}

template <class Real>
void FoldGuardT<Real>::build_edges(const SoftBodyT<Real>& body) {
    if (edges_wanted_) edges_.build(body, start_, near_, k_edge_radius * scale_.edge, on_);
    else edges_.reset();
}

template <class Real>
void FoldGuardT<Real>::mark_around(const SoftBodyT<Real>& body, uint32_t t, std::vector<uint8_t>& redo) {
    // Every particle whose neighbourhood may hold t: within the radius of it at rest, reached
    // through the corners as gather() reaches it.
    const std::vector<Vec3f>& rest = body.rest_positions;
    const mesh::Triangle& tri = body.triangles[t];
    const Vec3f &a = rest[tri[0]], &b = rest[tri[1]], &c = rest[tri[2]];
    const float r2 = scale_.exclusion * scale_.exclusion;
    const auto within = [&](uint32_t v) {
        const Vec2f w = mesh::closest_point_barycentric(rest[v], a, b, c);
        return (a + w.x() * (b - a) + w.y() * (c - a) - rest[v]).squaredNorm() < r2;
    };
    queue_.clear();
    for (const uint32_t k : tri)
        if (vertex_stamp_[k] != t) vertex_stamp_[k] = t, queue_.push_back(k);
    for (size_t q = 0; q < queue_.size(); ++q) {
        redo[queue_[q]] = 1;
        for (const uint32_t u : body.rings.triangles.of(queue_[q]))
            for (const uint32_t k : body.triangles[u])
                if (k < redo.size() && vertex_stamp_[k] != t && within(k)) vertex_stamp_[k] = t, queue_.push_back(k);
    }
}

template <class Real>
bool FoldGuardT<Real>::update(const SoftBodyT<Real>& body) {
    const size_t n = body.particle_count(), nt = body.triangles.size();
    if (start_.empty() || !(scale_.edge > 0.0f) || n < built_particles_ || nt < built_triangles_ || built_triangles_list_.size() != built_triangles_ ||
        body.rest_positions.size() != n || body.rings.triangles.keys() < n)
        return false;
    std::vector<uint8_t> redo(n, 0);
    for (size_t i = built_particles_; i < n; ++i) redo[i] = 1;
    vertex_stamp_.assign(n, UINT32_MAX);
    for (uint32_t t = 0; t < nt; ++t)
        if (t >= built_triangles_ || body.triangles[t] != built_triangles_list_[t]) {
            if (t < built_triangles_)
                for (const uint32_t k : built_triangles_list_[t]) redo[k] = 1;
            if (live(body.triangles[t], n, body.piece_of_particle)) mark_around(body, t, redo);
        }
    std::swap(start_, old_start_), std::swap(near_, old_near_);
    start_.assign(n + 1, 0);
    near_.clear();
    vertex_stamp_.assign(n, UINT32_MAX);
    triangle_stamp_.assign(nt, UINT32_MAX);
    for (uint32_t i = 0; i < n; ++i) {
        start_[i] = uint32_t(near_.size());
        if (!redo[i]) near_.insert(near_.end(), old_near_.begin() + old_start_[i], old_near_.begin() + old_start_[i + 1]);
        else if (body.piece_of_particle[i] != k_no_piece) gather(body, i, scale_.exclusion, near_);
    }
    start_[n] = uint32_t(near_.size());
    built_particles_ = n, built_triangles_ = nt, built_pieces_ = body.pieces;
    built_triangles_list_ = body.triangles;
    build_edges(body);
    return true;
}

template <class Real>
void FoldGuardT<Real>::frame_triangles(const SoftBodyT<Real>& body) {
    const ParticlesT<Real>& p = body.particles;
    const size_t n = p.size();
    spheres_.resize(body.triangles.size());
    planes_.resize(body.triangles.size());
    for (size_t t = 0; t < body.triangles.size(); ++t) {
        const mesh::Triangle& tri = body.triangles[t];
        TrianglePlanes& f = planes_[t];
        spheres_[t] = {Vec4f(0.0f, 0.0f, 0.0f, -1.0f), Vec4f::Zero()};
        if (!live(tri, n, body.piece_of_particle)) continue;
        const Vec3f a = pos3(p.x[tri[0]]), b = pos3(p.x[tri[1]]), c = pos3(p.x[tri[2]]);
        const Vec3f a0 = pos3(p.x_prev[tri[0]]), b0 = pos3(p.x_prev[tri[1]]), c0 = pos3(p.x_prev[tri[2]]);
        const Vec3f nrm = unit_normal(a, b, c), nrm0 = unit_normal(a0, b0, c0);
        if (nrm.isZero() || nrm0.isZero()) continue;  // degenerate: no side to keep
        const Vec3f m = (a + b + c) / 3.0f;
        const float r = std::sqrt(std::max({(a - m).squaredNorm(), (b - m).squaredNorm(), (c - m).squaredNorm()}));
        spheres_[t] = {Vec4f(m.x(), m.y(), m.z(), r), Vec4f(nrm.x(), nrm.y(), nrm.z(), 0.0f)};
        f.plane = Vec4f(nrm.x(), nrm.y(), nrm.z(), nrm.dot(a));
        f.plane0 = Vec4f(nrm0.x(), nrm0.y(), nrm0.z(), nrm0.dot(a0));
    }
}

template <class Real>
void FoldGuardT<Real>::find(const SoftBodyT<Real>& body, const ContactSettings& s, bool stiff_bodies) {
    active_.clear();
    edges_.clear_candidates();
    if (!s.enabled || !s.folds || stiff_bodies) return;
    edges_wanted_ = s.fold_edges;
    if (stale(body, s) && (s.thickness != settings_thickness_ || !update(body))) build(body, s);
    if (!(scale_.edge > 0.0f)) return;
    if (edges_wanted_ && !edges_.built()) build_edges(body);
    thickness_ = std::min(k_fold_thickness * scale_.edge, scale_.thickness);
    frame_triangles(body);
    if (edges_wanted_) folded_.assign(body.particle_count(), 1);
    // Particles in contiguous chunks, one list each, joined in chunk order: the candidates and
    // their order are one thread's for any thread count.
    const size_t n = body.particle_count();
    const unsigned chunks = pool_ && pool_->size() > 1 && n >= k_particles_per_chunk * pool_->chunks() ? pool_->chunks() : 1u;
    chunk_.resize(chunks);
    const auto run = [&](unsigned chunk, size_t begin, size_t end) {
        chunk_[chunk].clear();
        scan(body, uint32_t(begin), uint32_t(end), chunk_[chunk]);
    };
    if (chunks > 1) pool_->parallel_for(n, run);
    else run(0, 0, n);
    if (edges_wanted_) edges_.find(body, folded_, thickness_, thickness_ + scale_.slack);
    if (chunks == 1) return active_.swap(chunk_[0]);
    for (const std::vector<Candidate>& c : chunk_) active_.insert(active_.end(), c.begin(), c.end());
}

template <class Real>
void FoldGuardT<Real>::scan(const SoftBodyT<Real>& body, uint32_t first, uint32_t last, std::vector<Candidate>& out) {
    const ParticlesT<Real>& p = body.particles;
    const float reach = thickness_ + scale_.slack;
    const bool normals = body.normals.size() == body.particle_count();
    for (uint32_t i = first; i < last; ++i) {
        // Without its normal (a body not yet stepped), any neighbourhood may be folded.
        if (edges_wanted_) {
            const Vec3f ni = normals ? body.normals[i] : Vec3f::Zero();
            float turn = normals ? 1.0f : -1.0f;
            for (uint32_t k = start_[i]; k < start_[i + 1] && turn >= k_folded; ++k)
                turn = std::min(turn, ni.dot(spheres_[near_[k]].normal.template head<3>()));
            folded_[i] = turn < k_folded ? 1 : 0;
        }
        if (!(p.w[i] > Real(0))) continue;  // pinned or asleep: a fold reaches it through its neighbours
        const Vec3f xi = pos3(p.x[i]), xi0 = pos3(p.x_prev[i]);
        for (uint32_t k = start_[i]; k < start_[i + 1]; ++k) {
            const uint32_t t = near_[k];
            const Vec4f& sphere = spheres_[t].sphere;
            const float r = sphere.w() + reach;
            if (sphere.w() < 0.0f || (xi - sphere.head<3>()).squaredNorm() > r * r) continue;
            const TrianglePlanes& f = planes_[t];
            const float side = xi0.dot(f.plane0.template head<3>()) >= f.plane0.w() ? 1.0f : -1.0f;
            if (side * (xi.dot(f.plane.template head<3>()) - f.plane.w()) > reach) continue;  // clear of it, on its side
            // Its side is known only where it was over the triangle when the substep began: one
            // beside it then may have come round its edge, not through it.
            const mesh::Triangle& tri = body.triangles[t];
            const Over then = over_triangle(xi0, pos3(p.x_prev[tri[0]]), pos3(p.x_prev[tri[1]]), pos3(p.x_prev[tri[2]]),
                                            f.plane0.template head<3>());
            if (then.lateral > reach) continue;
            out.push_back({i, tri[0], tri[1], tri[2], side});
        }
    }
}

template <class Real>
void FoldGuardT<Real>::project(ParticlesT<Real>& p) const {
    for (const Candidate& ct : active_) {
        const uint32_t i = ct.particle;
        const Vec3f a = pos3(p.x[ct.a]), b = pos3(p.x[ct.b]), c = pos3(p.x[ct.c]);
        const Vec3f nf = unit_normal(a, b, c);
        if (nf.isZero()) continue;
        const Vec3f xi = pos3(p.x[i]);
        if (ct.side * (xi - a).dot(nf) >= thickness_) continue;
        const Over o = over_triangle(xi, a, b, c, nf);
        // Only over it: beside it, the particle is over a neighbour of it or clear of the fold.
        if (o.lateral > k_over * scale_.edge) continue;
        const Real C = Real(ct.side) * Real(o.height) - Real(thickness_);
        if (C >= Real(0)) continue;
        // Far through it already: it came there some other way (round an edge, pushed by a
        // constraint), and pulling it back across would tear its neighbourhood apart.
        if (C < -Real(thickness_ + scale_.slack)) continue;
        const Real ua = Real(o.wa), ub = Real(o.wb), uc = Real(o.wc);
        const Real denom = p.w[i] + ua * ua * p.w[ct.a] + ub * ub * p.w[ct.b] + uc * uc * p.w[ct.c];
        if (!(denom > Real(0))) continue;
        const Vec4<Real> d = (-C / denom) * Real(ct.side) * to4<Real>(nf);
        p.x[i] += p.w[i] * d;
        p.x[ct.a] -= p.w[ct.a] * ua * d;
        p.x[ct.b] -= p.w[ct.b] * ub * d;
        p.x[ct.c] -= p.w[ct.c] * uc * d;
    }
    edges_.project(p);
}

template class FoldGuardT<float>;
template class FoldGuardT<double>;

} // namespace pbdsplat::sim
