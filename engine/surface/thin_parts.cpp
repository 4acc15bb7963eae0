#include "surface/thin_parts.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "mesh/topology.h"

namespace pbdsplat::surface {

float mean_thickness(double volume, double area) { return area > 0.0 ? float(4.0 * std::abs(volume) / area) : 0.0f; }

namespace {

// Per part: closed where none of its vertices lies on an open boundary loop.
std::vector<char> closed_parts(const mesh::TriangleMesh& m, const std::vector<uint32_t>& part_of_triangle, uint32_t parts) {
    std::vector<uint32_t> part_of_vertex(m.positions.size(), parts);
    for (size_t t = 0; t < m.triangles.size(); ++t)
        for (uint32_t v : m.triangles[t]) part_of_vertex[v] = part_of_triangle[t];
    std::vector<char> closed(parts, 1);
    for (const auto& loop : mesh::boundary_loops(m))
        for (uint32_t v : loop)
            if (part_of_vertex[v] < parts) closed[part_of_vertex[v]] = 0;
    return closed;
}

} // namespace

float spacing_for_thin_parts(const mesh::TriangleMesh& m, float below) {
    constexpr float none = std::numeric_limits<float>::infinity();
    std::vector<uint32_t> part;
    const uint32_t parts = mesh::vertex_components(m.triangles, m.positions.size(), part);
    if (parts == 0) return none;
    std::vector<double> volume(parts, 0.0), area(parts, 0.0);
    double total = 0.0;
    for (size_t t = 0; t < m.triangles.size(); ++t) {
        const Vec3d a = m.positions[m.triangles[t][0]].cast<double>(), b = m.positions[m.triangles[t][1]].cast<double>(),
                    c = m.positions[m.triangles[t][2]].cast<double>();
        const double da = 0.5 * (b - a).cross(c - a).norm();
        volume[part[t]] += a.dot(b.cross(c)) / 6.0;
        area[part[t]] += da;
        total += da;
    }
    if (!(total > 0.0) || !std::isfinite(total)) return none;
    // The parts that would ask for less than `below`, thinnest first to be tested for closure.
    std::vector<std::pair<float, uint32_t>> asking;
    for (uint32_t c = 0; c < parts; ++c) {
        if (area[c] < double(k_thin_part_area_share) * total) continue;
        const float t = mean_thickness(volume[c], area[c]);
        if (t > 0.0f && std::isfinite(t) && k_spacing_over_thickness * t < below) asking.emplace_back(t, c);
    }
    if (asking.empty()) return none;
    std::sort(asking.begin(), asking.end());
    const std::vector<char> closed = closed_parts(m, part, parts);
    float thinnest = none;
    for (const auto& [t, c] : asking)
        if (closed[c]) {
            thinnest = t;
            break;
        }
    return thinnest < none ? k_spacing_over_thickness * thinnest : none;
}

} // namespace pbdsplat::surface
