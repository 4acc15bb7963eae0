#include "pbdsplat/sim_baseline.h"

#include <cmath>
#include <cstddef>
#include <vector>

#include "mesh/topology.h"
#include "sim/vec4_ops.h"

namespace pbdsplat::cli {

namespace {
Vec4f cross4(const Vec4f& a, const Vec4f& b) {
    return Vec4f(a.y() * b.z() - a.z() * b.y(), a.z() * b.x() - a.x() * b.z(), a.x() * b.y() - a.y() * b.x(), 0.0f);
}

// Reorders `edges` so that, where it can within a small lookahead, no edge shares a particle
// with the `k_gap` edges emitted before it. Still one sequential Gauss-Seidel sweep, in a
// different order.
template <class Edge> std::vector<Edge> interleave(const std::vector<Edge>& edges) {
    constexpr size_t k_gap = 3, k_lookahead = 64;
    std::vector<Edge> out, deferred;
    out.reserve(edges.size());
    const auto clashes = [&](const Edge& e) {
        for (size_t k = 1; k <= k_gap && k <= out.size(); ++k) {
            const Edge& o = out[out.size() - k];
            if (e.i == o.i || e.i == o.j || e.j == o.i || e.j == o.j) return true;
        }
        return false;
    };
    const auto emit_deferred = [&]() {
        for (size_t d = 0; d < deferred.size(); ++d)
            if (!clashes(deferred[d])) {
                out.push_back(deferred[d]);
                deferred.erase(deferred.begin() + std::ptrdiff_t(d));
                return true;
            }
        return false;
    };
    for (const Edge& e : edges) {
        while (emit_deferred()) {
        }
        if (!clashes(e)) {
            out.push_back(e);
        } else {
            deferred.push_back(e);
            if (deferred.size() > k_lookahead) {  // nothing fits: give up on the oldest
                out.push_back(deferred.front());
                deferred.erase(deferred.begin());
            }
        }
    }
    while (!deferred.empty())
        if (!emit_deferred()) {
            out.push_back(deferred.front());
            deferred.erase(deferred.begin());
        }
    return out;
}
} // namespace

SimBaseline::SimBaseline(const mesh::TriangleMesh& m, uint32_t pinned, const Settings& settings)
    : s_(settings), triangles_(m.triangles) {
    const size_t n = m.positions.size();
    x_.resize(n), p_.resize(n), v_.assign(n, Vec4f::Zero()), grad_.resize(n), n_.resize(n), w_.assign(n, 0.0f);
    for (size_t i = 0; i < n; ++i) x_[i] = Vec4f(m.positions[i].x(), m.positions[i].y(), m.positions[i].z(), 0.0f);
    std::vector<double> mass(n, 0.0);
    double total = 0.0;
    for (const auto& t : m.triangles) {
        const double a = 0.5 * double((m.positions[t[1]] - m.positions[t[0]]).cross(m.positions[t[2]] - m.positions[t[0]]).norm());
        for (uint32_t v : t) mass[v] += a / 3.0;
        total += a;
    }
    for (size_t i = 0; i < n; ++i) w_[i] = mass[i] > 0.0 ? float(total / mass[i]) : 0.0f;  // total mass 1
    if (pinned < n) w_[pinned] = 0.0f;
    for (const mesh::Edge& e : mesh::unique_edges(m)) edges_.push_back({e.a, e.b, (m.positions[e.a] - m.positions[e.b]).norm()});
    if (s_.tuned) prepare_tuned();
    for (const auto& t : triangles_) rest_volume_ += double(x_[t[0]].dot(cross4(x_[t[1]], x_[t[2]]))) / 6.0;
}

void SimBaseline::prepare_tuned() {
    std::erase_if(edges_, [&](const Edge& e) { return w_[e.i] + w_[e.j] == 0.0f; });
    for (Edge& e : edges_) {
        const float wsum = w_[e.i] + w_[e.j];
        e.share_i = w_[e.i] / wsum, e.share_j = w_[e.j] / wsum;
    }
    edges_ = interleave(edges_);
    const size_t n = x_.size();
    ring_start_.assign(n + 1, 0);
    for (const auto& t : triangles_)
        for (uint32_t v : t) ++ring_start_[v + 1];
    for (size_t i = 0; i < n; ++i) ring_start_[i + 1] += ring_start_[i];
    ring_.resize(ring_start_[n]);
    std::vector<uint32_t> fill(ring_start_.begin(), ring_start_.end() - 1);
    for (const auto& t : triangles_)
        for (int k = 0; k < 3; ++k) ring_[fill[t[k]]++] = {t[(k + 1) % 3], t[(k + 2) % 3]};
}

void SimBaseline::step(float dt) {
    const size_t n = x_.size();
    const Vec4f dv(s_.gravity.x() * dt, s_.gravity.y() * dt, s_.gravity.z() * dt, 0.0f);
    const float keep = std::exp(-s_.damping * dt);
    for (size_t i = 0; i < n; ++i) {
        if (w_[i] > 0.0f) v_[i] = (v_[i] + dv) * keep;
        p_[i] = x_[i] + dt * v_[i];
    }
    const auto per_iteration = [&](float k) { return k >= 1.0f ? 1.0f : 1.0f - std::pow(1.0f - k, 1.0f / float(s_.iterations)); };
    const float ks = per_iteration(s_.stretch_stiffness), kv = per_iteration(s_.volume_stiffness);
    for (uint32_t it = 0; it < s_.iterations; ++it) {
        if (s_.tuned) project_edges_tuned(ks);
        else project_edges_plain(ks);
        if (!s_.volume) continue;
        if (s_.tuned) project_volume_tuned(kv);
        else project_volume_plain(kv);
    }
    const float inv = 1.0f / dt;
    for (size_t i = 0; i < n; ++i) {
        v_[i] = w_[i] > 0.0f ? Vec4f((p_[i] - x_[i]) * inv) : Vec4f::Zero();
        x_[i] = p_[i];
    }
    if (s_.tuned) update_normals_tuned();
    else update_normals_plain();
}

void SimBaseline::update_normals_plain() {
    std::fill(n_.begin(), n_.end(), Vec3f::Zero());
    for (const auto& t : triangles_) {
        const Vec4f f = cross4(x_[t[1]] - x_[t[0]], x_[t[2]] - x_[t[0]]);
        for (uint32_t v : t) n_[v] += f.head<3>();
    }
    for (Vec3f& nv : n_) nv.normalize();
}

void SimBaseline::update_normals_tuned() {
    // Gathered from the ring: the sum of the incident faces' area vectors.
    for (size_t i = 0; i < x_.size(); ++i) {
        Vec4f f = Vec4f::Zero();
        for (uint32_t r = ring_start_[i]; r < ring_start_[i + 1]; ++r)
            f += sim::cross3<float>(x_[ring_[r].first] - x_[i], x_[ring_[r].second] - x_[i]);
        n_[i] = f.head<3>().normalized();
    }
}

void SimBaseline::project_volume_plain(float kv) {
    const size_t n = x_.size();
    std::fill(grad_.begin(), grad_.end(), Vec4f::Zero());
    double six_v = 0.0;
    for (const auto& t : triangles_) {
        const Vec4f &a = p_[t[0]], &b = p_[t[1]], &c = p_[t[2]];
        six_v += double(a.dot(cross4(b, c)));
        grad_[t[0]] += cross4(b, c);
        grad_[t[1]] += cross4(c, a);
        grad_[t[2]] += cross4(a, b);
    }
    double denom = 0.0;
    for (size_t i = 0; i < n; ++i) denom += double(w_[i]) * double(grad_[i].squaredNorm());
    if (denom < 1e-30) return;
    const float step = float(-double(kv) * (six_v / 6.0 - rest_volume_) / (denom / 36.0) / 6.0);
    for (size_t i = 0; i < n; ++i) p_[i] += (step * w_[i]) * grad_[i];
}

void SimBaseline::project_volume_tuned(float kv) {
    // Each triangle's a . (b x c) is summed once per corner: three times the volume's 6V.
    const size_t n = x_.size();
    float six_v_3 = 0.0f, denom = 0.0f;
    for (size_t i = 0; i < n; ++i) {
        Vec4f g = Vec4f::Zero();
        for (uint32_t r = ring_start_[i]; r < ring_start_[i + 1]; ++r) g += sim::cross3<float>(p_[ring_[r].first], p_[ring_[r].second]);
        grad_[i] = g;
        six_v_3 += p_[i].dot(g);
        denom += w_[i] * g.squaredNorm();
    }
    if (denom < 1e-30f) return;
    const float step = float(-double(kv) * (double(six_v_3) / 18.0 - rest_volume_) / (double(denom) / 36.0) / 6.0);
    for (size_t i = 0; i < n; ++i) p_[i] += (step * w_[i]) * grad_[i];
}

void SimBaseline::project_edges_plain(float ks) {
    for (const Edge& e : edges_) {
        const float wsum = w_[e.i] + w_[e.j];
        const Vec4f d = p_[e.i] - p_[e.j];
        const float len = d.norm();
        if (wsum == 0.0f || len < 1e-12f) continue;
        const Vec4f corr = (ks * (len - e.rest) / (len * wsum)) * d;
        p_[e.i] -= w_[e.i] * corr;
        p_[e.j] += w_[e.j] * corr;
    }
}

void SimBaseline::project_edges_tuned(float ks) {
    for (const Edge& e : edges_) {
        const Vec4f d = p_[e.i] - p_[e.j];
        const float len = d.norm();
        if (len < 1e-12f) continue;
        const Vec4f corr = (ks * (len - e.rest) / len) * d;
        p_[e.i] -= e.share_i * corr;
        p_[e.j] += e.share_j * corr;
    }
}

} // namespace pbdsplat::cli
