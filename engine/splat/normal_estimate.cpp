#include "splat/normal_estimate.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <queue>
#include <tuple>
#include <vector>

#include <Eigen/Eigenvalues>

#include "surface/point_grid.h"

namespace pbdsplat::splat {
namespace {

// A Gaussian counts as flat when its shortest axis is under half the middle one: then that
// axis is the surface normal it was trained to be (and a neighbour fit would only blur it).
constexpr float k_flat_ratio = 0.5f;
// Neighbours for the plane fit: enough for a stable fit on a noisy capture, few enough to stay
// local across a crease.
constexpr uint32_t k_neighbours = 12;
// A plane needs its two in-plane spreads well above the normal one.
constexpr float k_planarity = 0.25f;

// The neighbour graph made symmetric (j near i or i near j), in compressed rows.
struct Graph {
    std::vector<uint32_t> start, to;
    std::span<const uint32_t> of(size_t i) const { return {to.data() + start[i], to.data() + start[i + 1]}; }
};

Graph symmetric(const std::vector<std::vector<uint32_t>>& near) {
    Graph g;
    const size_t n = near.size();
    std::vector<uint32_t> degree(n, 0);
    for (size_t i = 0; i < n; ++i)
        for (uint32_t j : near[i]) ++degree[i], ++degree[j];
    g.start.assign(n + 1, 0);
    for (size_t i = 0; i < n; ++i) g.start[i + 1] = g.start[i] + degree[i];
    g.to.resize(g.start[n]);
    std::vector<uint32_t> fill(g.start.begin(), g.start.end() - 1);
    for (size_t i = 0; i < n; ++i)
        for (uint32_t j : near[i]) g.to[fill[i]++] = j, g.to[fill[j]++] = uint32_t(i);
    return g;
}


// Step 1: an unsigned normal for Gaussian i, from its shape when it is flat, else from the
// plane of its neighbours (`near`, filled). 0: none found; 1: found, sign still open.
enum class Source { none, shape, neighbours };
Source unsigned_normal(size_t i, std::span<const Vec3f> centres, std::span<const GaussianShape> shapes, const surface::PointGrid& grid,
                       std::vector<uint32_t>& near, Vec3f& normal) {
    grid.k_nearest(centres[i], uint32_t(i), k_neighbours, 8, near);
    if (!shapes.empty()) {
        const Eigen::Matrix3f axes = shape_axes(shapes[i]);
        std::array<std::pair<float, int>, 3> len = {{{axes.col(0).norm(), 0}, {axes.col(1).norm(), 1}, {axes.col(2).norm(), 2}}};
        std::sort(len.begin(), len.end());
        if (len[0].first > 0.0f && len[0].first < k_flat_ratio * len[1].first) {
            normal = axes.col(len[0].second).normalized();
            return Source::shape;
        }
    }
    if (near.size() < 3) return Source::none;
    Vec3f mean = centres[i];
    for (uint32_t j : near) mean += centres[j];
    mean /= float(near.size() + 1);
    Eigen::Matrix3f scatter = (centres[i] - mean) * (centres[i] - mean).transpose();
    for (uint32_t j : near) scatter += (centres[j] - mean) * (centres[j] - mean).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3f> eig(scatter);
    const Vec3f ev = eig.eigenvalues();  // ascending
    if (!(ev[0] < k_planarity * ev[1])) return Source::none;
    normal = eig.eigenvectors().col(0);
    return Source::neighbours;
}

// Step 2: signs. Facing away from the centre is wrong wherever the surface folds back (a
// bunny's ears, its feet), so the sign travels instead: along the neighbour graph, flattest
// turns first (a spanning tree that maximises |n_i . n_j|), each node taking the side of the
// one it was reached from. Trees grow from the file's own normals (state 2), and in pieces
// without any, from the point furthest from the centre, whose outward side is certain.
// `state`: 0 no normal, 1 unsigned, 2 from the file.
void orient(const Graph& g, std::span<const Vec3f> centres, const Vec3f& centroid, std::span<const uint8_t> state,
            std::vector<Vec3f>& normal) {
    const size_t n = centres.size();
    std::vector<uint8_t> done(n, 0);
    using Step = std::tuple<float, uint32_t, uint32_t>;  // (1 - |n_from . n_to|, to, from)
    std::priority_queue<Step, std::vector<Step>, std::greater<Step>> frontier;
    auto grow = [&]() {
        while (!frontier.empty()) {
            const auto [cost, i, from] = frontier.top();
            frontier.pop();
            if (done[i]) continue;
            done[i] = 1;
            if (state[i] == 1 && from != i && normal[i].dot(normal[from]) < 0.0f) normal[i] = -normal[i];
            for (uint32_t j : g.of(i))
                if (!done[j] && state[j] != 0) frontier.emplace(1.0f - std::abs(normal[i].dot(normal[j])), j, uint32_t(i));
        }
    };
    for (size_t i = 0; i < n; ++i)
        if (state[i] == 2) frontier.emplace(0.0f, uint32_t(i), uint32_t(i));
    grow();
    std::vector<uint32_t> by_reach(n);
    std::iota(by_reach.begin(), by_reach.end(), 0u);
    std::sort(by_reach.begin(), by_reach.end(), [&](uint32_t a, uint32_t b) {
        return (centres[a] - centroid).squaredNorm() > (centres[b] - centroid).squaredNorm();
    });
    for (uint32_t seed : by_reach) {
        if (done[seed] || state[seed] != 1) continue;
        if (normal[seed].dot(centres[seed] - centroid) < 0.0f) normal[seed] = -normal[seed];
        frontier.emplace(0.0f, seed, seed);
        grow();
    }
}

} // namespace

NormalEstimate estimate_normals(std::span<GaussianRecord> records, std::span<const GaussianShape> shapes,
                                std::span<const uint8_t> missing) {
    NormalEstimate out;
    const size_t n = records.size();
    if (n == 0) return out;
    std::vector<Vec3f> centres(n), normal(n);
    Vec3f centroid = Vec3f::Zero();
    for (size_t i = 0; i < n; ++i) {
        centres[i] = Vec3f(records[i].position[0], records[i].position[1], records[i].position[2]);
        normal[i] = decode_octahedral(records[i].normal_oct);
        centroid += centres[i];
    }
    centroid /= float(n);
    // Cells about the spacing of points on a surface: its bounding area over the count.
    Vec3f lo = centres[0], hi = centres[0];
    for (const Vec3f& p : centres) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    const Vec3f e = (hi - lo).cwiseMax(Vec3f::Constant(1e-6f));
    const float area = 2.0f * (e.x() * e.y() + e.y() * e.z() + e.z() * e.x());
    surface::PointGrid grid(std::max(std::sqrt(area / float(n)), 1e-6f), n);
    for (const Vec3f& p : centres) grid.add(p);

    std::vector<uint8_t> state(n, 2);  // 0: none found, 1: unsigned, 2: the file's own
    std::vector<std::vector<uint32_t>> near(n);
    for (size_t i = 0; i < n; ++i) {
        if (missing[i]) {
            const Source source = unsigned_normal(i, centres, shapes, grid, near[i], normal[i]);
            state[i] = source == Source::none ? 0 : 1;
            out.from_shape += source == Source::shape ? 1 : 0;
            out.from_neighbours += source == Source::neighbours ? 1 : 0;
            out.unresolved += source == Source::none ? 1 : 0;
        } else {
            grid.k_nearest(centres[i], uint32_t(i), k_neighbours, 8, near[i]);  // they pass signs on
        }
    }
    orient(symmetric(near), centres, centroid, state, normal);
    for (size_t i = 0; i < n; ++i)
        if (state[i] == 1) encode_octahedral(normal[i], records[i].normal_oct);
    return out;
}

} // namespace pbdsplat::splat
