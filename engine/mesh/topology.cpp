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
    // Directed edges with no twin are boundary; on a manifold mesh each boundary vertex has one
    // outgoing boundary edge, so following them closes every loop.
    std::unordered_map<uint64_t, uint32_t> directed;
    directed.reserve(mesh.triangles.size() * 3);
    auto key = [](uint32_t a, uint32_t b) { return (uint64_t(a) << 32) | b; };
    for (const Triangle& t : mesh.triangles)
        for (int k = 0; k < 3; ++k) directed[key(t[size_t(k)], t[size_t((k + 1) % 3)])] = 1;
    std::unordered_map<uint32_t, uint32_t> next;  // boundary vertex -> next along the loop
    std::vector<uint32_t> starts;
    for (const Triangle& t : mesh.triangles)
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = t[size_t(k)], b = t[size_t((k + 1) % 3)];
            if (!directed.count(key(b, a))) {
                // Reverse direction: the loop runs against its triangles, as a hole's rim does
                // when seen from outside, so a fan over it continues the surface outward.
                next[b] = a;
                starts.push_back(b);
            }
        }
    std::vector<std::vector<uint32_t>> loops;
    std::unordered_map<uint32_t, bool> used;
    for (uint32_t s : starts) {
        if (used[s]) continue;
        std::vector<uint32_t> loop;
        uint32_t v = s;
        while (!used[v]) {
            used[v] = true;
            loop.push_back(v);
            auto it = next.find(v);
            if (it == next.end()) break;  // not closed: only possible on a non-manifold input
            v = it->second;
        }
        if (loop.size() >= 3) loops.push_back(std::move(loop));
    }
    return loops;
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

} // namespace pbdsplat::mesh
