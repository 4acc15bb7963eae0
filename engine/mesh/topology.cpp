#include "mesh/topology.h"

#include <algorithm>
#include <numeric>
#include <unordered_map>

namespace pbdsplat::mesh {

std::vector<Edge> unique_edges(const TriangleMesh& mesh) {
    std::vector<Edge> edges;
    edges.reserve(mesh.triangles.size() * 3);
    for (const Triangle& t : mesh.triangles)
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = t[size_t(k)], b = t[size_t((k + 1) % 3)];
            edges.push_back({std::min(a, b), std::max(a, b)});
        }
    std::sort(edges.begin(), edges.end(), [](Edge x, Edge y) { return x.a != y.a ? x.a < y.a : x.b < y.b; });
    edges.erase(std::unique(edges.begin(), edges.end(), [](Edge x, Edge y) { return x.a == y.a && x.b == y.b; }),
                edges.end());
    return edges;
}

std::vector<std::vector<uint32_t>> boundary_loops(const TriangleMesh& mesh) {
    return boundary_loops(std::span<const Triangle>(mesh.triangles), mesh.positions.size());
}

uint32_t triangle_components(const TriangleMesh& mesh, std::vector<uint32_t>& component) {
    const size_t n = mesh.triangles.size();
    std::vector<uint32_t> parent(n);
    std::iota(parent.begin(), parent.end(), 0u);
    auto find = [&](uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    std::unordered_map<uint64_t, uint32_t> first_face;
    first_face.reserve(n * 3);
    for (uint32_t f = 0; f < n; ++f)
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = mesh.triangles[f][size_t(k)], b = mesh.triangles[f][size_t((k + 1) % 3)];
            const uint64_t key = (uint64_t(std::min(a, b)) << 32) | std::max(a, b);
            auto [it, inserted] = first_face.try_emplace(key, f);
            if (!inserted) parent[find(f)] = find(it->second);
        }
    component.assign(n, UINT32_MAX);
    std::unordered_map<uint32_t, uint32_t> id;
    for (uint32_t f = 0; f < n; ++f) {
        auto [it, inserted] = id.try_emplace(find(f), uint32_t(id.size()));
        component[f] = it->second;
    }
    return uint32_t(id.size());
}

std::vector<std::vector<uint32_t>> boundary_loops(std::span<const Triangle> triangles, size_t vertex_count) {
    // Outgoing directed edges per vertex in CSR form; (a, b) is a boundary edge when b has no
    // edge back to a. On a manifold mesh each boundary vertex has one outgoing boundary edge,
    // so following them closes every loop; elsewhere the last edge seen wins and an open chain
    // ends where it runs out.
    std::vector<uint32_t> start(vertex_count + 1, 0), to(triangles.size() * 3);
    for (const Triangle& t : triangles)
        for (uint32_t v : t) ++start[v + 1];
    for (size_t v = 0; v < vertex_count; ++v) start[v + 1] += start[v];
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    for (const Triangle& t : triangles)
        for (int k = 0; k < 3; ++k) to[fill[t[size_t(k)]]++] = t[size_t((k + 1) % 3)];
    auto has_edge = [&](uint32_t a, uint32_t b) {
        for (uint32_t e = start[a]; e < start[a + 1]; ++e)
            if (to[e] == b) return true;
        return false;
    };
    constexpr uint32_t none = UINT32_MAX;
    std::vector<uint32_t> next(vertex_count, none);
    std::vector<uint32_t> starts;
    for (const Triangle& t : triangles)
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = t[size_t(k)], b = t[size_t((k + 1) % 3)];
            if (!has_edge(b, a)) {
                // Reverse direction: the loop runs against its triangles, as a hole's rim does
                // when seen from outside, so a fan over it continues the surface outward.
                next[b] = a;
                starts.push_back(b);
            }
        }
    std::vector<std::vector<uint32_t>> loops;
    std::vector<uint8_t> used(vertex_count, 0);
    for (uint32_t s : starts) {
        if (used[s]) continue;
        std::vector<uint32_t> loop;
        for (uint32_t v = s; v != none && !used[v]; v = next[v]) {
            used[v] = 1;
            loop.push_back(v);
        }
        if (loop.size() >= 3) loops.push_back(std::move(loop));
    }
    return loops;
}

uint32_t vertex_components(std::span<const Triangle> triangles, size_t vertex_count, std::vector<uint32_t>& component) {
    std::vector<uint32_t> parent(vertex_count);
    std::iota(parent.begin(), parent.end(), 0u);
    auto find = [&](uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    for (const Triangle& t : triangles) {
        const uint32_t r = find(t[0]);
        parent[find(t[1])] = r;
        parent[find(t[2])] = find(t[0]);
    }
    constexpr uint32_t none = UINT32_MAX;
    std::vector<uint32_t> id(vertex_count, none);
    uint32_t count = 0;
    component.resize(triangles.size());
    for (size_t f = 0; f < triangles.size(); ++f) {
        uint32_t& c = id[find(triangles[f][0])];
        if (c == none) c = count++;
        component[f] = c;
    }
    return count;
}

} // namespace pbdsplat::mesh
