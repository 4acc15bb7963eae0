#include "surface/thin_order.h"

#include <cmath>

#include "surface/point_grid.h"

namespace pbdsplat::surface {

namespace {
// Which of six cones around the axes a normal lies in: samples in different cones never block
// each other.
uint32_t normal_side(const Vec3f& n) {
    const Vec3f a = n.cwiseAbs();
    const uint32_t axis = a.x() >= a.y() && a.x() >= a.z() ? 0u : a.y() >= a.z() ? 1u : 2u;
    return 2u * axis + (n[int(axis)] < 0.0f ? 1u : 0u);
}

float level_radius(float h, int level) { return h * std::exp2(0.5f * float(level)); }
} // namespace

void place_in_thin_order(std::span<const Vec3f> position, std::span<const Vec3f> normal, std::span<const uint32_t> tag, float h,
                         std::vector<uint8_t>& level, std::span<const Vec3f> gaps) {
    const size_t n = position.size(), first_new = std::min(level.size(), n);
    level.resize(n, 0);
    if ((first_new == n && gaps.empty()) || !(h > 0.0f)) return;
    // The order is made afresh around the new samples (within twice the widest radius of them:
    // the gaps that samples removed near them left are filled too), the samples around that
    // (within three times it) keeping theirs as fixed neighbours. Elsewhere nothing changes.
    Eigen::AlignedBox3f around;
    for (size_t i = first_new; i < n; ++i) around.extend(position[i]);
    for (const Vec3f& g : gaps) around.extend(g);
    const float reach = level_radius(h, k_thin_levels);
    const Eigen::AlignedBox3f remade(around.min() - Vec3f::Constant(2.0f * reach), around.max() + Vec3f::Constant(2.0f * reach));
    const Eigen::AlignedBox3f fixed(around.min() - Vec3f::Constant(3.0f * reach), around.max() + Vec3f::Constant(3.0f * reach));
    std::vector<uint32_t> neighbours, placed;
    for (size_t i = 0; i < n; ++i) {
        if (i >= first_new || remade.contains(position[i])) {
            placed.push_back(uint32_t(i));
            level[i] = 0;
        } else if (level[i] > 0 && fixed.contains(position[i])) {
            neighbours.push_back(uint32_t(i));
        }
    }
    std::vector<uint32_t> key(n);
    for (uint32_t i : placed) key[i] = (tag.empty() ? 0u : tag[i]) * 6u + normal_side(normal[i]);
    for (uint32_t i : neighbours) key[i] = (tag.empty() ? 0u : tag[i]) * 6u + normal_side(normal[i]);
    // Coarsest level first: a sample rises to level l unless a sample placed at l lies within
    // R(l), or a fixed neighbour j within R(min(l, level j)) (every level's set stays a Poisson
    // disc, the finer ones too).
    PointGrid grid(h, neighbours.size() + placed.size());
    std::vector<uint32_t> sample_of;  // the grid's points, in the order added
    for (int l = k_thin_levels; l >= 1; --l) {
        const float r = level_radius(h, l);
        grid.reset(2.0f * r);
        sample_of.clear();
        for (uint32_t i : neighbours) grid.add(position[i], key[i]), sample_of.push_back(i);
        for (uint32_t i : placed)
            if (level[i] >= l) grid.add(position[i], key[i]), sample_of.push_back(i);
        for (uint32_t i : placed) {
            if (level[i] >= l) continue;
            const bool blocked = grid.near_within_if(position[i], r, [&](uint32_t g) {
                const uint32_t j = sample_of[g];
                if (key[j] != key[i]) return false;
                const float rj = level_radius(h, std::min(l, int(level[j])));
                return (position[j] - position[i]).squaredNorm() < rj * rj;
            });
            if (blocked) continue;
            level[i] = uint8_t(l);
            grid.add(position[i], key[i]);
            sample_of.push_back(i);
        }
    }
}

} // namespace pbdsplat::surface
