#include "sim/weld.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "mesh/topology.h"
#include "sim/distance.h"

namespace pbdsplat::sim {

size_t weld_touching_parts(SoftBody& b, float reach, WeldFrom from) {
    const std::vector<float> same(b.model_count(), reach);
    return weld_touching_parts(b, same, from);
}

std::vector<float> mean_rest_edge_of_models(const SoftBody& b) {
    auto model = [&](size_t i) { return i < b.model_of_particle.size() ? b.model_of_particle[i] : 0u; };
    std::vector<double> sum;
    std::vector<size_t> count;
    for (const DistanceConstraint& d : b.distance) {
        if (!d.alive()) continue;
        const uint32_t m = model(d.i);
        if (m >= sum.size()) sum.resize(m + 1, 0.0), count.resize(m + 1, 0);
        sum[m] += double(d.rest), ++count[m];
    }
    std::vector<float> out(sum.size(), 0.0f);
    for (size_t m = 0; m < out.size(); ++m)
        if (count[m]) out[m] = float(sum[m] / double(count[m]));
    return out;
}

size_t weld_touching_parts(SoftBody& b, std::span<const float> reach_of_model, WeldFrom from) {
    const size_t n = b.particle_count();
    auto model = [&](size_t i) { return i < b.model_of_particle.size() ? b.model_of_particle[i] : 0u; };
    const auto reach_of = [&](size_t i) { return model(i) < reach_of_model.size() ? reach_of_model[model(i)] : 0.0f; };
    float reach = 0.0f;  // the grid's cell: the widest reach
    for (float r : reach_of_model)
        if (r > reach) reach = r;
    if (!(reach > 0.0f) || !std::isfinite(reach) || b.part_of_particle.size() != n) return 0;
    auto cell = [&](const Vec3f& x) { return Eigen::Vector3i((x / reach).array().floor().cast<int>()); };
    auto key = [](const Eigen::Vector3i& c) {
        return (uint64_t(uint32_t(c.x()) & 0x1fffff) << 42) ^ (uint64_t(uint32_t(c.y()) & 0x1fffff) << 21) ^ uint64_t(uint32_t(c.z()) & 0x1fffff);
    };
    // Only particles on the surface count (a particle no triangle uses is not part of a part).
    std::vector<char> used(n, 0);
    for (const mesh::Triangle& t : b.triangles)
        for (uint32_t v : t) used[v] = 1;
    // A weld starts at an open edge of its part (where a spout or a handle ends on the body, or a
    // lid's rim sits on the pot's) or, where `from` says, anywhere on a closed part.
    std::vector<char> seed(n, 0);
    uint32_t parts = 0;
    for (uint32_t i = 0; i < n; ++i)
        if (used[i]) parts = std::max(parts, b.part_of_particle[i] + 1);
    std::vector<char> open_part(parts, 0);
    for (const auto& loop : mesh::boundary_loops(b.triangles, n))
        for (uint32_t v : loop) {
            seed[v] = 1;
            if (b.part_of_particle[v] < open_part.size()) open_part[b.part_of_particle[v]] = 1;
        }
    if (from == WeldFrom::open_edges_and_closed_parts)
        for (uint32_t i = 0; i < n; ++i)
            if (used[i] && b.part_of_particle[i] < open_part.size() && !open_part[b.part_of_particle[i]]) seed[i] = 1;
    std::unordered_map<uint64_t, std::vector<uint32_t>> grid;
    for (uint32_t i = 0; i < n; ++i)
        if (used[i]) grid[key(cell(xyz(b.particles.x[i])))].push_back(i);
    std::vector<std::pair<uint32_t, uint32_t>> pairs;
    for (uint32_t i = 0; i < n; ++i) {
        if (!seed[i]) continue;
        const Vec3f xi = xyz(b.particles.x[i]);
        const Eigen::Vector3i c = cell(xi);
        float best = reach_of(i) * reach_of(i);
        uint32_t nearest = UINT32_MAX;
        for (int dx = -1; dx <= 1; ++dx)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dz = -1; dz <= 1; ++dz) {
                    const auto it = grid.find(key(c + Eigen::Vector3i(dx, dy, dz)));
                    if (it == grid.end()) continue;
                    for (uint32_t j : it->second) {
                        if (b.part_of_particle[j] == b.part_of_particle[i] || model(j) != model(i)) continue;
                        const float d2 = (xyz(b.particles.x[j]) - xi).squaredNorm();
                        if (d2 < best || (d2 == best && j < nearest)) best = d2, nearest = j;
                    }
                }
        if (nearest != UINT32_MAX) pairs.emplace_back(std::min(i, nearest), std::max(i, nearest));
    }
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    for (const auto& [i, j] : pairs) b.welds.push_back({i, j, (xyz(b.particles.x[i]) - xyz(b.particles.x[j])).norm(), 0.0f});
    return pairs.size();
}

template <class Real>
void project_welds(const BodyStructureT<Real>& b, ParticlesT<Real>& p, Real stiffness) {
    // One at a time: welds share particles (a body particle may hold several of a spout's).
    for (const DistanceConstraint& w : b.welds) project_distance_pbd<Real>(std::span<const DistanceConstraint>(&w, 1), p, stiffness);
}

template void project_welds<float>(const BodyStructureT<float>&, ParticlesT<float>&, float);
template void project_welds<double>(const BodyStructureT<double>&, ParticlesT<double>&, double);

} // namespace pbdsplat::sim
