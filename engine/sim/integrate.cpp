#include "sim/integrate.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/assert.h"
#include "core/radix_sort.h"
#include "core/small_sort.h"
#include "sim/vec4_ops.h"

namespace pbdsplat::sim {

template <class Real>
void apply_forces_and_predict(ParticlesT<Real>& p, const Vec3f& gravity, float damping, Real dt, size_t begin, size_t end) {
    const Vec4<Real> dv = dt * to4<Real>(gravity);
    const Real keep = damping > 0.0f ? std::exp(-Real(damping) * dt) : Real(1);
    for (size_t i = begin; i < end; ++i) {
        if (p.w[i] != Real(0)) p.v[i] = (p.v[i] + dv) * keep;  // pinned particles do not move
        p.x_prev[i] = p.x[i];
        p.x[i] += dt * p.v[i];
    }
}

template <class Real>
void apply_forces_and_predict(ParticlesT<Real>& p, const Vec3f& gravity, std::span<const Real> keep, std::span<const uint32_t> model, Real dt,
                              size_t begin, size_t end) {
    const Vec4<Real> dv = dt * to4<Real>(gravity);
    for (size_t i = begin; i < end; ++i) {
        if (p.w[i] != Real(0)) p.v[i] = (p.v[i] + dv) * keep[model[i]];
        p.x_prev[i] = p.x[i];
        p.x[i] += dt * p.v[i];
    }
}

template <class Real>
void update_velocities(ParticlesT<Real>& p, Real dt, size_t begin, size_t end) {
    const Real inv = Real(1) / dt;
    for (size_t i = begin; i < end; ++i)
        p.v[i] = p.w[i] > Real(0) ? Vec4<Real>((p.x[i] - p.x_prev[i]) * inv) : Vec4<Real>::Zero();
}

VertexRings build_vertex_rings(std::span<const mesh::Triangle> triangles, size_t vertex_count) {
    std::vector<uint32_t> start(vertex_count + 1, 0);
    for (const auto& t : triangles)
        for (uint32_t v : t) ++start[v + 1];
    for (size_t i = 0; i < vertex_count; ++i) start[i + 1] += start[i];
    std::vector<std::array<uint32_t, 2>> ring(start.back());
    std::vector<uint32_t> index(start.back());
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    for (uint32_t f = 0; f < triangles.size(); ++f) {
        const mesh::Triangle& t = triangles[f];
        for (int c = 0; c < 3; ++c) {
            const uint32_t slot = fill[t[size_t(c)]]++;
            ring[slot] = {t[size_t((c + 1) % 3)], t[size_t((c + 2) % 3)]};
            index[slot] = f;
        }
    }
    VertexRings r;
    r.ring.build(start, ring);
    r.triangles.build(start, index);
    return r;
}

void update_vertex_rings(VertexRings& rings, std::span<const mesh::Triangle> triangles, size_t vertex_count,
                         std::span<const uint32_t> vertices, std::span<const uint32_t> extra) {
    rings.ring.grow(vertex_count);
    rings.triangles.grow(vertex_count);
    // Per vertex, the extra triangles having it as a corner: sorted (vertex, triangle) pairs.
    std::vector<uint64_t> by_vertex;  // vertex << 32 | triangle
    by_vertex.reserve(3 * extra.size());
    for (uint32_t f : extra)
        for (uint32_t v : triangles[f]) by_vertex.push_back(uint64_t(v) << 32 | f);
    core::radix_sort(std::span(by_vertex));
    std::vector<uint32_t> mine;
    std::vector<std::array<uint32_t, 2>> ring;
    // `vertices` ascend, as do the pairs: one walk along both instead of a search per vertex.
    PBDSPLAT_ASSERT(std::is_sorted(vertices.begin(), vertices.end()), "update_vertex_rings: sort the vertices ascending first");
    auto it = by_vertex.begin();
    for (uint32_t v : vertices) {
        mine.clear();
        for (uint32_t f : rings.triangles.of(v))
            if (f < triangles.size()) mine.push_back(f);
        while (it != by_vertex.end() && uint32_t(*it >> 32) < v) ++it;
        for (; it != by_vertex.end() && uint32_t(*it >> 32) == v; ++it) mine.push_back(uint32_t(*it));
        core::insertion_sort(mine.begin(), mine.end());  // a vertex has a handful of triangles
        mine.erase(std::unique(mine.begin(), mine.end()), mine.end());
        ring.clear();
        size_t kept = 0;
        for (uint32_t f : mine) {
            const mesh::Triangle& t = triangles[f];
            const int c = t[0] == v ? 0 : t[1] == v ? 1 : t[2] == v ? 2 : -1;
            if (c < 0) continue;  // it lost this corner to a copy
            mine[kept++] = f;
            ring.push_back({t[size_t((c + 1) % 3)], t[size_t((c + 2) % 3)]});
        }
        mine.resize(kept);
        rings.ring.assign(v, ring);
        rings.triangles.assign(v, mine);
    }
}

void update_rest_ring_areas(VertexRings& rings, std::span<const Vec3f> rest, std::span<const uint32_t> vertices) {
    rings.rest_area.resize(rings.size(), 0.0f);
    rings.open_fan.resize(rings.size(), 0);
    for (uint32_t i : vertices) {
        Vec3f acc = Vec3f::Zero();
        const auto ring = rings.ring.of(i);
        bool open = false;
        float longest2 = 0.0f;
        for (const auto& r : ring) {
            acc += (rest[r[0]] - rest[i]).cross(rest[r[1]] - rest[i]);
            longest2 = std::max({longest2, (rest[r[0]] - rest[i]).squaredNorm(), (rest[r[1]] - rest[i]).squaredNorm()});
            // Closed: every neighbour that starts a triangle's pair ends another's.
            open = open || std::none_of(ring.begin(), ring.end(), [&](const auto& q) { return q[1] == r[0]; });
        }
        // A fan of slivers at rest (a vertex a cut put near an edge's end) counts as a quarter of
        // its longest edge squared: it is no stretched region when it opens up.
        rings.rest_area[i] = std::max(acc.norm(), 0.25f * longest2);
        rings.open_fan[i] = open;
    }
}

void set_rest_ring_areas(VertexRings& rings, std::span<const Vec3f> rest) {
    std::vector<uint32_t> all(rings.size());
    std::iota(all.begin(), all.end(), 0u);
    update_rest_ring_areas(rings, rest, all);
}

void update_normals(const VertexRings& rings, const Vec4Array& x, std::vector<Vec3f>& normals, size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
        Vec4f acc = Vec4f::Zero();
        for (const auto& r : rings.ring.of(uint32_t(i)))
            acc += cross3<float>(x[r[0]] - x[i], x[r[1]] - x[i]);  // twice the area, outward
        const float len = acc.norm();
        normals[i] = len > 0.0f ? Vec3f(acc.head<3>() / len) : Vec3f(0.0f, 1.0f, 0.0f);
    }
}

template void apply_forces_and_predict<float>(ParticlesT<float>&, const Vec3f&, float, float, size_t, size_t);
template void apply_forces_and_predict<double>(ParticlesT<double>&, const Vec3f&, float, double, size_t, size_t);
template void apply_forces_and_predict<float>(ParticlesT<float>&, const Vec3f&, std::span<const float>, std::span<const uint32_t>, float, size_t,
                                             size_t);
template void apply_forces_and_predict<double>(ParticlesT<double>&, const Vec3f&, std::span<const double>, std::span<const uint32_t>, double,
                                              size_t, size_t);
template void update_velocities<float>(ParticlesT<float>&, float, size_t, size_t);
template void update_velocities<double>(ParticlesT<double>&, double, size_t, size_t);

bool edge_on_boundary(const VertexRings& rings, std::span<const mesh::Triangle> triangles, uint32_t t, uint32_t a, uint32_t b) {
    for (uint32_t f : rings.triangles.of(a))
        if (f != t && std::ranges::find(triangles[f], b) != triangles[f].end()) return false;
    return true;
}

} // namespace pbdsplat::sim
