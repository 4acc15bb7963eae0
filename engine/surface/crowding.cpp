#include "surface/crowding.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "core/assert.h"
#include "surface/point_grid.h"
#include "surface/rows.h"

namespace pbdsplat::surface {
namespace {

// Which cells of a grid some point's ball reaches, as bits of a small hashed bitmap: each point
// added marks the cells its ball of radius `reach` (at most half a cell) meets, at most the 2 x
// 2 x 2 on its nearer side along each axis, so a query reads the one bit of its own cell, from
// cache, and rejects most of a large set tested against a small one before any lookup in the
// grid itself (70k samples kept as they are against a few dozen candidates: 2 ms with eight
// lookups each, 4-5 ms of hash probing without the bitmap). Marking the 27 cells around each
// point instead set 2.4 times the bits on bunny_cut and let 19 % of the kept samples through to
// the grid against 11.6 %: each false positive costs the real test.
class CellBits {
public:
    CellBits(float cell, float reach) : inv_(1.0f / cell), reach_(reach * inv_), bits_(k_words, 0) {
        PBDSPLAT_ASSERT(reach_ <= 0.5f + 1e-5f, "CellBits: a reach of more than half a cell meets cells beyond the nearer neighbours; use larger cells");
    }
    void add(const Vec3f& p) {
        const Vec3f u = p * inv_;
        const Eigen::Vector3i c = math::floor_to_int(u);
        // Per axis the cells from the ball's low end to its high end: the point's own and, where
        // the ball crosses a face, the one beyond it (a hair wider: a miss here would be a miss).
        int lo[3], hi[3];
        for (int a = 0; a < 3; ++a) {
            const float f = u[a] - float(c[a]);
            lo[a] = f < reach_ * 1.0001f + 1e-6f ? -1 : 0;
            hi[a] = 1.0f - f < reach_ * 1.0001f + 1e-6f ? 1 : 0;
        }
        for (int dz = lo[2]; dz <= hi[2]; ++dz)
            for (int dy = lo[1]; dy <= hi[1]; ++dy)
                for (int dx = lo[0]; dx <= hi[0]; ++dx) {
                    const uint32_t b = bit(c + Eigen::Vector3i(dx, dy, dz));
                    bits_[b >> 6] |= uint64_t(1) << (b & 63);
                }
    }
    bool maybe_near(const Vec3f& p) const {
        const uint32_t b = bit(cell(p));
        return (bits_[b >> 6] >> (b & 63)) & 1u;
    }

private:
    static constexpr size_t k_words = 4096;  // 262,144 bits, 32 KB
    Eigen::Vector3i cell(const Vec3f& p) const { return math::floor_to_int(Vec3f(p * inv_)); }
    static uint32_t bit(const Eigen::Vector3i& c) {
        const uint64_t k = (uint64_t(uint32_t(c.x())) * 0x9E3779B97F4A7C15ull) ^ (uint64_t(uint32_t(c.y())) * 0xC2B2AE3D27D4EB4Full) ^
                           (uint64_t(uint32_t(c.z())) * 0x165667B19E3779F9ull);
        return uint32_t(k >> 46);  // 18 bits
    }
    float inv_;
    float reach_;  // in cells
    std::vector<uint64_t> bits_;
};

} // namespace

namespace {

// Unit normals of the triangles (zero for a degenerate one).
std::vector<Vec3f> face_normals(std::span<const Vec4f> x, std::span<const mesh::Triangle> triangles) {
    std::vector<Vec3f> face(triangles.size());
    for (size_t t = 0; t < triangles.size(); ++t) {
        const mesh::Triangle& c = triangles[t];
        const Vec3f n = (x[c[1]] - x[c[0]]).head<3>().cross((x[c[2]] - x[c[0]]).head<3>());
        const float len = n.norm();
        face[t] = len > 0.0f ? Vec3f(n / len) : Vec3f::Zero();
    }
    return face;
}

// The samples by rank: on triangles that did not shrink (kept as they are), or candidates,
// settled ones first, then those fading in, each in storage order. Edge samples stay out of it:
// they lie h/2 apart along a boundary with smaller splats on purpose, and the interior ones
// beside them cover what they do not. A byte per sample marks the kept ones, not a list: they
// are most of a body (65k of the bunny's 70k at a check), and listing them cost more than the
// test that reads them.
constexpr uint8_t k_kept = 0, k_candidate = 1, k_out = 2;
struct Ranks {
    std::vector<uint8_t> rank;
    std::vector<uint32_t> candidates;
    size_t kept_as_they_are = 0;
};
Ranks rank_samples(const BoundaryParticles& s, const CrowdingQuery& q) {
    Ranks r;
    r.rank.resize(s.size());
    std::vector<uint32_t> fading_in;
    for (size_t i = 0; i < s.size(); ++i) {
        if (s.retiring(i) || s.on_edge(i)) {
            r.rank[i] = k_out;
        } else if (!q.changed.empty() && (q.changed[s.triangle[i]] & k_shrank) == 0) {
            r.rank[i] = k_kept;
            ++r.kept_as_they_are;
        } else {
            r.rank[i] = k_candidate;
            (s.fade_step[i] > 0.0f ? fading_in : r.candidates).push_back(uint32_t(i));
        }
    }
    r.candidates.insert(r.candidates.end(), fading_in.begin(), fading_in.end());
    return r;
}

constexpr float k_same_side = 0.5f;  // cos 60 degrees, as the spacing figure counts

// Which candidates lie within the crowd radius of a sample kept as it is, or of a particle drawn
// as a splat, facing the same way. The candidates go into a small grid of cells 2 `crowd` h wide,
// each test reading the 8 nearest; the samples kept as they are and the particles then look for
// candidates near them there, so the large set is read once in order and never gridded
// (gridding the bunny's 70k samples kept as they are took 3-4 ms a check).
std::vector<uint8_t> pressed_candidates(std::span<const Vec4f> x, std::span<const Vec3f> normals, const std::vector<Vec3f>& face,
                                        const BoundaryParticles& s, const Ranks& r, size_t anchors, float crowd_r) {
    const std::vector<uint32_t>& candidates = r.candidates;
    std::vector<uint8_t> crowded(candidates.size(), 0);
    PointGrid grid(2.0f * crowd_r, candidates.size());
    // The bitmap pays where the candidates are few against what tests them; where most of the
    // body shrank (a balloon let down), marking its cells for each costs more than it saves.
    std::optional<CellBits> cells;
    if (candidates.size() * 4 < r.kept_as_they_are + anchors) cells.emplace(2.0f * crowd_r, crowd_r);
    for (uint32_t i : candidates) {
        grid.add(s.position[i]);
        if (cells) cells->add(s.position[i]);
    }
    std::vector<Vec3f> candidate_side(candidates.size());
    for (size_t k = 0; k < candidates.size(); ++k) candidate_side[k] = face[s.triangle[candidates[k]]];
    auto press = [&](const Vec3f& p, const Vec3f& n) {
        if (cells && !cells->maybe_near(p)) return;
        grid.each_within(p, crowd_r, [&](uint32_t k) {
            if (candidate_side[k].dot(n) >= k_same_side) crowded[k] = 1;
            return true;
        });
    };
    for (size_t v = 0; v < anchors; ++v) press(x[v].head<3>(), v < normals.size() ? normals[v] : Vec3f::Zero());
    for (size_t i = 0; i < s.size(); ++i)
        if (r.rank[i] == k_kept) press(s.position[i], face[s.triangle[i]]);
    return crowded;
}

// The grown triangles whose centre nothing kept covers. A grown triangle's centre is covered by
// what is kept around it: its own samples, those of the triangles sharing a vertex with it, and
// those triangles' corners where the particles are drawn. A surface sampled at h is never so
// crumpled inside a grown triangle that cover comes from farther away; and no grid is built
// (gridding every sample of an inflating body, each of its triangles grown, was half of the check).
std::vector<uint32_t> uncovered(std::span<const Vec4f> x, std::span<const Vec3f> normals, std::span<const mesh::Triangle> triangles,
                                const std::vector<Vec3f>& face, const CrowdingQuery& q, const BoundaryParticles& s,
                                const std::vector<uint8_t>& rank, size_t anchors) {
    std::vector<uint32_t> gaps;
    const float gap_r2 = (q.gap * q.h) * (q.gap * q.h);
    const Rows by_triangle = make_rows(triangles.size(), s.size(), [&](size_t i) { return s.triangle[i]; },
                                       [&](size_t i) { return rank[i] == k_kept; });
    Rows own_ring;
    if (!q.ring) own_ring = corner_rows(x.size(), triangles);
    const Rows& ring = q.ring ? *q.ring : own_ring;
    std::vector<uint32_t> mark(triangles.size(), ~0u);
    for (uint32_t t = 0; t < triangles.size(); ++t) {
        if ((!q.changed.empty() && (q.changed[t] & k_grew) == 0) || face[t].isZero()) continue;
        const mesh::Triangle& c = triangles[t];
        const Vec3f centre = ((x[c[0]] + x[c[1]] + x[c[2]]) / 3.0f).head<3>();
        const Vec3f& n = face[t];
        auto covers = [&](const Vec3f& p, const Vec3f& side) { return (p - centre).squaredNorm() < gap_r2 && side.dot(n) >= k_same_side; };
        auto covered_by = [&](uint32_t u) {
            for (uint32_t i : by_triangle[u])
                if (covers(s.position[i], face[u])) return true;
            if (anchors)
                for (uint32_t v : triangles[u])
                    if (covers(x[v].head<3>(), v < normals.size() ? normals[v] : Vec3f::Zero())) return true;
            return false;
        };
        // Its own samples first: they cover it most often.
        bool covered = covered_by(t);
        mark[t] = t;
        for (int k = 0; k < 3 && !covered; ++k)
            for (uint32_t corner : ring[c[k]]) {
                const uint32_t u = corner / 3;
                if (mark[u] == t) continue;
                mark[u] = t;
                if ((covered = covered_by(u))) break;
            }
        if (!covered) gaps.push_back(t);
    }
    return gaps;
}

} // namespace

CrowdingResult thin_crowds(std::span<const Vec4f> x, std::span<const Vec3f> normals, std::span<const mesh::Triangle> triangles,
                           const CrowdingQuery& q, BoundaryParticles& s) {
    CrowdingResult out;
    s.pad_fades();
    PBDSPLAT_ASSERT(q.changed.empty() || q.changed.size() == triangles.size(), "thin_crowds: give one changed flag per triangle, or none");
    const std::vector<Vec3f> face = face_normals(x, triangles);
    Ranks r = rank_samples(s, q);
    const size_t anchors = q.anchors_drawn ? x.size() : 0;  // the particles, when they are splats
    const float crowd_r = std::max(q.crowd, 0.05f) * q.h;
    const std::vector<uint32_t>& candidates = r.candidates;
    const std::vector<uint8_t> crowded =
        q.crowd > 0.0f && !candidates.empty() ? pressed_candidates(x, normals, face, s, r, anchors, crowd_r) : std::vector<uint8_t>(candidates.size(), 0);
    // Among the candidates, the older stay: the settled first, then those fading in, each in
    // storage order.
    PointGrid kept(2.0f * crowd_r, candidates.size());
    std::vector<uint32_t> kept_candidates;
    std::vector<Vec3f> kept_side;
    kept_side.reserve(candidates.size());
    for (size_t k = 0; k < candidates.size(); ++k) {
        const uint32_t i = candidates[k];
        const Vec3f& n = face[s.triangle[i]];
        if (q.crowd > 0.0f && out.retired < q.max_retired &&
            (crowded[k] || kept.near_within_if(s.position[i], crowd_r, [&](uint32_t j) { return kept_side[j].dot(n) >= k_same_side; }))) {
            s.fade_step[i] = -q.fade_step;
            ++out.retired;
            continue;
        }
        kept.add(s.position[i]);
        kept_candidates.push_back(i);
        kept_side.push_back(n);
    }
    if (q.gap > 0.0f) {
        for (uint32_t i : kept_candidates) r.rank[i] = k_kept;
        out.gaps = uncovered(x, normals, triangles, face, q, s, r.rank, anchors);
    }
    return out;
}

} // namespace pbdsplat::surface
