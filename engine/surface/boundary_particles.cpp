#include "surface/boundary_particles.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <bit>

#include "core/assert.h"

namespace pbdsplat::surface {
namespace {

// A hash grid of accepted points with cell size h: any point within h lies in the 27 cells
// around a query. Open addressing over cell keys, with the points of a cell chained through
// an index array: sampling asks it millions of times, so no node allocation and no rehash of
// vectors.
class PointGrid {
public:
    PointGrid(float h, size_t expected_points) : inv_h_(1.0f / h), h2_(h * h) {
        size_t cap = 1024;
        while (cap < expected_points * 2) cap <<= 1;
        keys_.assign(cap, k_empty);
        heads_.assign(cap, k_end);
        mask_ = cap - 1;
        shift_ = 64 - std::countr_zero(cap);
        points_.reserve(expected_points);
        next_.reserve(expected_points);
    }
    bool near(const Vec3f& p) const {
        const Eigen::Vector3i c = cell(p);
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const size_t slot = find(key(c + Eigen::Vector3i(dx, dy, dz)));
                    if (slot == k_end) continue;
                    for (uint32_t i = heads_[slot]; i != k_end; i = next_[i])
                        if ((points_[i] - p).squaredNorm() < h2_) return true;
                }
        return false;
    }
    void add(const Vec3f& p) {
        if ((points_.size() + 1) * 2 > keys_.size()) grow();
        const uint64_t k = key(cell(p));
        size_t slot = slot_of(k);
        while (keys_[slot] != k_empty && keys_[slot] != k) slot = (slot + 1) & mask_;
        keys_[slot] = k;
        next_.push_back(heads_[slot]);
        heads_[slot] = uint32_t(points_.size());
        points_.push_back(p);
    }

private:
    static constexpr uint64_t k_empty = ~0ull;
    static constexpr uint32_t k_end = ~0u;
    // Fibonacci hashing: the high bits of the product mix all of x, y and z.
    size_t slot_of(uint64_t k) const { return size_t((k * 0x9E3779B97F4A7C15ull) >> shift_); }
    size_t find(uint64_t k) const {
        size_t slot = slot_of(k);
        while (true) {
            if (keys_[slot] == k) return slot;
            if (keys_[slot] == k_empty) return k_end;
            slot = (slot + 1) & mask_;
        }
    }
    void grow() {
        std::vector<Vec3f> old = std::move(points_);
        const size_t cap = keys_.size() * 2;
        keys_.assign(cap, k_empty);
        heads_.assign(cap, k_end);
        mask_ = cap - 1;
        shift_ = 64 - std::countr_zero(cap);
        points_.clear();
        next_.clear();
        for (const Vec3f& q : old) add(q);
    }
    Eigen::Vector3i cell(const Vec3f& p) const { return (p * inv_h_).array().floor().cast<int>(); }
    static uint64_t key(const Eigen::Vector3i& c) {
        return (uint64_t(uint32_t(c.x()) & 0x1fffff) << 42) | (uint64_t(uint32_t(c.y()) & 0x1fffff) << 21) |
               uint64_t(uint32_t(c.z()) & 0x1fffff);
    }
    float inv_h_, h2_;
    size_t mask_ = 0;
    int shift_ = 54;
    std::vector<uint64_t> keys_;
    std::vector<uint32_t> heads_;  // per slot: the newest point in that cell
    std::vector<uint32_t> next_;   // per point: the next point in its cell
    std::vector<Vec3f> points_;
};

// The rest surface being sampled, without owning (or copying) it.
struct SurfaceView {
    std::span<const Vec3f> positions;
    std::span<const mesh::Triangle> triangles;
};

struct Candidate {
    uint32_t triangle;
    Vec2f bary;
    Vec3f position;
};

// Uniform random candidates over the triangles, `density` per unit area; shuffled so that the
// greedy pass below is dart throwing (blue noise) rather than a scan.
std::vector<Candidate> candidates(const SurfaceView& m, std::span<const uint32_t> triangles, float density,
                                  std::mt19937& rng) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<Candidate> out;
    for (uint32_t t : triangles) {
        const auto& tri = m.triangles[t];
        const Vec3f& a = m.positions[tri[0]];
        const Vec3f& b = m.positions[tri[1]];
        const Vec3f& c = m.positions[tri[2]];
        const float area = 0.5f * (b - a).cross(c - a).norm();
        const float expected = area * density;
        uint32_t n = uint32_t(expected);
        if (u(rng) < expected - float(n)) ++n;
        for (uint32_t k = 0; k < n; ++k) {
            float r1 = u(rng), r2 = u(rng);
            if (r1 + r2 > 1.0f) r1 = 1.0f - r1, r2 = 1.0f - r2;  // fold into the triangle: uniform
            out.push_back({t, Vec2f(r1, r2), a + r1 * (b - a) + r2 * (c - a)});
        }
    }
    std::shuffle(out.begin(), out.end(), rng);
    return out;
}

Vec3f position_of(const SurfaceView& m, uint32_t t, const Vec2f& b) {
    const auto& tri = m.triangles[t];
    return (1.0f - b.x() - b.y()) * m.positions[tri[0]] + b.x() * m.positions[tri[1]] + b.y() * m.positions[tri[2]];
}

void accept(const SurfaceView& m, const std::vector<Candidate>& cands, PointGrid& grid, BoundaryParticles& out) {
    for (const Candidate& c : cands) {
        if (grid.near(c.position)) continue;
        grid.add(c.position);
        out.triangle.push_back(c.triangle);
        out.bary.push_back(c.bary);
        out.position.push_back(c.position);
        const auto& tri = m.triangles[c.triangle];
        out.normal.push_back((m.positions[tri[1]] - m.positions[tri[0]]).cross(m.positions[tri[2]] - m.positions[tri[0]]).normalized());
    }
}

} // namespace

void BoundaryParticles::clear() {
    triangle.clear();
    bary.clear();
    position.clear();
    normal.clear();
}

float spacing(const mesh::TriangleMesh& m, float eta) { return eta * mesh::mean_edge_length(m); }

BoundaryParticles sample_surface(const mesh::TriangleMesh& m, const SamplingOptions& o) {
    std::vector<uint32_t> all(m.triangles.size());
    for (uint32_t t = 0; t < all.size(); ++t) all[t] = t;
    BoundaryParticles out;
    fill_triangles(m, all, o, out);
    return out;
}

void fill_triangles(const mesh::TriangleMesh& mesh, std::span<const uint32_t> triangles, const SamplingOptions& o,
                    BoundaryParticles& samples) {
    fill_triangles(mesh.positions, mesh.triangles, triangles, o, samples);
}

void fill_triangles(std::span<const Vec3f> positions, std::span<const mesh::Triangle> all_triangles,
                    std::span<const uint32_t> triangles, const SamplingOptions& o, BoundaryParticles& samples) {
    const SurfaceView m{positions, all_triangles};
    PBDSPLAT_ASSERT(o.h > 0.0f && std::isfinite(o.h), "boundary particle spacing h must be positive");
    // Only points near the triangles can block a candidate: a local refill stays local.
    Eigen::AlignedBox3f near;
    for (uint32_t t : triangles)
        for (uint32_t v : m.triangles[t]) near.extend(m.positions[v]);
    if (near.isEmpty()) return;
    near.min().array() -= o.h;
    near.max().array() += o.h;
    PointGrid grid(o.h, triangles.size() == m.triangles.size() ? m.positions.size() + samples.size() + 1024 : 1024);
    for (const Vec3f& v : m.positions)
        if (near.contains(v)) grid.add(v);  // the simulation particles are samples too
    for (size_t i = 0; i < samples.size(); ++i) {
        const Vec3f p = position_of(m, samples.triangle[i], samples.bary[i]);
        if (near.contains(p)) grid.add(p);
    }
    std::mt19937 rng(o.seed);
    accept(m, candidates(m, triangles, o.candidates / (o.h * o.h), rng), grid, samples);
}

void update_boundary_particles(std::span<const mesh::Triangle> triangles, std::span<const Vec4f> x,
                               std::span<const Vec3f> n, BoundaryParticles& s) {
    const size_t count = s.size();
    s.position.resize(count);
    s.normal.resize(count);
    const uint32_t* tri_index = s.triangle.data();
    const Vec2f* bary = s.bary.data();
    for (size_t i = 0; i < count; ++i) {
        const auto& t = triangles[tri_index[i]];
        const float b1 = bary[i].x(), b2 = bary[i].y(), b0 = 1.0f - b1 - b2;
        const Vec4f p = b0 * x[t[0]] + b1 * x[t[1]] + b2 * x[t[2]];
        s.position[i] = p.head<3>();
        const Vec3f nn = b0 * n[t[0]] + b1 * n[t[1]] + b2 * n[t[2]];
        const float len = nn.norm();
        s.normal[i] = len > 0.0f ? Vec3f(nn / len) : n[t[0]];
    }
}

} // namespace pbdsplat::surface
