#include "sim/enclosure.h"

#include <algorithm>

#include "sim/closed_surface.h"

namespace pbdsplat::sim {

std::vector<std::pair<uint32_t, uint32_t>> find_enclosed_parts(const SoftBody& body) {
    std::vector<std::pair<uint32_t, uint32_t>> out;
    const size_t n = body.particle_count();
    if (body.rest_positions.size() != n || body.part_of_particle.size() != n || body.volumes.empty()) return out;
    // Each part's particles (those in a triangle) and rest box.
    uint32_t parts = 0;
    for (size_t i = 0; i < n; ++i)
        if (body.piece_of_particle[i] < body.pieces) parts = std::max(parts, body.part_of_particle[i] + 1);
    std::vector<std::vector<uint32_t>> members(parts);
    std::vector<Eigen::AlignedBox3f> box(parts);
    std::vector<uint32_t> part_of_piece(body.pieces, UINT32_MAX);
    for (size_t i = 0; i < n; ++i) {
        if (body.piece_of_particle[i] >= body.pieces) continue;
        const uint32_t part = body.part_of_particle[i];
        members[part].push_back(uint32_t(i));
        box[part].extend(body.rest_positions[i]);
        part_of_piece[body.piece_of_particle[i]] = part;
    }
    // Parts in order of their boxes' lowest x: a container's candidates are one run of them.
    std::vector<uint32_t> order;
    for (uint32_t k = 0; k < parts; ++k)
        if (!members[k].empty()) order.push_back(k);
    std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return box[a].min().x() < box[b].min().x(); });
    for (const ClosedSurface& s : closed_surfaces(body, true)) {
        const uint32_t outer = part_of_piece[s.piece];
        auto first = std::lower_bound(order.begin(), order.end(), s.box.min().x(), [&](uint32_t k, float x) { return box[k].min().x() < x; });
        for (auto it = first; it != order.end() && box[*it].min().x() <= s.box.max().x(); ++it) {
            const uint32_t inner = *it;
            if (inner == outer || !s.box.contains(box[inner])) continue;
            const std::vector<uint32_t>& m = members[inner];
            const size_t step = std::max<size_t>(1, m.size() / k_enclosure_samples);
            bool all = true;
            for (size_t j = 0; j < m.size() && all; j += step) all = inside(s, body.rest_positions[m[j]]);
            if (all) out.emplace_back(inner, outer);
        }
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

} // namespace pbdsplat::sim
