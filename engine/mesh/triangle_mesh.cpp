#include "mesh/triangle_mesh.h"

#include <algorithm>
#include <unordered_map>

namespace pbdsplat::mesh {
namespace {
uint64_t directed_key(uint32_t a, uint32_t b) { return (uint64_t(a) << 32) | b; }
uint64_t undirected_key(uint32_t a, uint32_t b) { return directed_key(std::min(a, b), std::max(a, b)); }

// Count of uses of each undirected edge.
std::unordered_map<uint64_t, int> edge_uses(const TriangleMesh& mesh) {
    std::unordered_map<uint64_t, int> uses;
    uses.reserve(mesh.triangles.size() * 2);
    for (const Triangle& t : mesh.triangles)
        for (int k = 0; k < 3; ++k) ++uses[undirected_key(t[size_t(k)], t[size_t((k + 1) % 3)])];
    return uses;
}
} // namespace

Bounds bounds(std::span<const Vec3f> points) {
    Bounds b;
    if (points.empty()) return b;
    b.min = b.max = points[0];
    for (const Vec3f& p : points) {
        b.min = b.min.cwiseMin(p);
        b.max = b.max.cwiseMax(p);
    }
    return b;
}

Bounds bounds(const TriangleMesh& mesh) { return bounds(std::span<const Vec3f>(mesh.positions)); }

std::vector<Vec3f> vertex_normals(const TriangleMesh& mesh) {
    std::vector<Vec3f> n(mesh.positions.size(), Vec3f::Zero());
    for (const Triangle& t : mesh.triangles) {
        const Vec3f& a = mesh.positions[t[0]];
        const Vec3f face = (mesh.positions[t[1]] - a).cross(mesh.positions[t[2]] - a);  // |face| = 2 area
        for (uint32_t v : t) n[v] += face;
    }
    for (Vec3f& v : n) {
        const float len = v.norm();
        v = len > 0.0f ? Vec3f(v / len) : Vec3f::Zero();
    }
    return n;
}

float mean_edge_length(const TriangleMesh& mesh) {
    double sum = 0.0;
    size_t count = 0;
    for (const auto& [key, uses] : edge_uses(mesh)) {
        (void)uses;
        const uint32_t a = uint32_t(key >> 32), b = uint32_t(key & 0xffffffffu);
        sum += double((mesh.positions[a] - mesh.positions[b]).norm());
        ++count;
    }
    return count ? float(sum / double(count)) : 0.0f;
}

size_t boundary_edge_count(const TriangleMesh& mesh) {
    size_t n = 0;
    for (const auto& [key, uses] : edge_uses(mesh)) n += uses == 1 ? 1 : 0;
    return n;
}

bool is_closed_and_oriented(const TriangleMesh& mesh) {
    std::unordered_map<uint64_t, int> directed;
    directed.reserve(mesh.triangles.size() * 3);
    for (const Triangle& t : mesh.triangles)
        for (int k = 0; k < 3; ++k)
            if (++directed[directed_key(t[size_t(k)], t[size_t((k + 1) % 3)])] > 1) return false;
    for (const auto& [key, count] : directed) {
        (void)count;
        const uint32_t a = uint32_t(key >> 32), b = uint32_t(key & 0xffffffffu);
        if (!directed.count(directed_key(b, a))) return false;
    }
    return !mesh.triangles.empty();
}

double signed_volume(const TriangleMesh& mesh) {
    double v = 0.0;
    for (const Triangle& t : mesh.triangles) {
        const Vec3d a = mesh.positions[t[0]].cast<double>();
        const Vec3d b = mesh.positions[t[1]].cast<double>();
        const Vec3d c = mesh.positions[t[2]].cast<double>();
        v += a.dot((b - a).cross(c - a));
    }
    return v / 6.0;
}

void append(TriangleMesh& into, const TriangleMesh& part, const Eigen::Affine3f& transform, const Vec3f& fill_color) {
    const size_t before = into.positions.size(), added = part.positions.size();
    const auto pad = [&](auto& mine, const auto& theirs, const auto& fill, auto map) {
        if (mine.empty() && theirs.empty()) return;
        mine.resize(before, fill);
        if (theirs.empty()) mine.resize(before + added, fill);
        else
            for (const auto& v : theirs) mine.push_back(map(v));
    };
    const Eigen::Matrix3f normal_map = transform.linear().inverse().transpose();
    pad(into.normals, part.normals, Vec3f::Zero(), [&](const Vec3f& n) { return Vec3f((normal_map * n).normalized()); });
    pad(into.uvs, part.uvs, Vec2f::Zero(), [](const Vec2f& uv) { return uv; });
    pad(into.colors, part.colors, fill_color, [](const Vec3f& c) { return c; });
    for (const Vec3f& p : part.positions) into.positions.push_back(transform * p);
    const uint32_t base = uint32_t(before);
    for (const Triangle& t : part.triangles) into.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
}

} // namespace pbdsplat::mesh
