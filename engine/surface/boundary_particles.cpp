#include "surface/boundary_particles.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <type_traits>
#include <random>

#include "core/assert.h"
#include "core/thread_pool.h"
#include "surface/embedding.h"
#include "surface/point_grid.h"

namespace pbdsplat::surface {
namespace {

// The rest surface being sampled, without owning (or copying) it.
struct SurfaceView {
    std::span<const Vec3f> positions;
    std::span<const mesh::Triangle> triangles;
};

// Twelve bytes: millions are made and shuffled, so the position is computed again when the
// candidate is tried (the same expression, so the same float) rather than stored.
struct Candidate {
    uint32_t triangle;
    Vec2f bary;
};

Vec3f candidate_position(const Vec3f& a, const Vec3f& b, const Vec3f& c, const Vec2f& r) {
    return a + r.x() * (b - a) + r.y() * (c - a);
}

// Uniform random candidates over the triangles, `density` per unit area, and the order they
// are tried in: shuffled, so that the greedy pass below is dart throwing (blue noise) rather
// than a scan. The order is shuffled as 4-byte indices rather than the candidates themselves:
// the same draws give the same permutation, with a third of the memory moved.
struct Candidates {
    std::vector<Candidate> all;
    std::vector<uint32_t> order;
};

// The permutation std::shuffle makes of `order` with `rng`, in two thirds of its time on
// millions of entries (seven million: 122 -> 82 ms). Past 2^16 entries libstdc++ swaps each
// entry i in turn with one drawn uniformly from [0, i], one draw a swap. The draws do not depend
// on the entries, so they are made some swaps ahead and the entries they name fetched while
// earlier swaps run: each swap was a cache miss. Below that size (or with another standard
// library) std::shuffle itself runs.
void shuffle_order(std::vector<uint32_t>& order, std::mt19937& rng) {
    const size_t n = order.size();
#if defined(__GLIBCXX__)
    using Index = std::make_unsigned_t<std::ptrdiff_t>;  // std::shuffle's draw type
    const Index range = Index(std::mt19937::max() - std::mt19937::min());
    if (n > 1 && range / Index(n) < Index(n)) {
        std::uniform_int_distribution<Index> pick;
        using Range = std::uniform_int_distribution<Index>::param_type;
        constexpr size_t k_lead = 32;  // a power of two
        Index drawn[k_lead];
        size_t next = 1;  // the next swap to draw for
        for (size_t i = 1; i < n; ++i) {
            for (; next < n && next < i + k_lead; ++next) {
                drawn[next & (k_lead - 1)] = pick(rng, Range(0, next));
                __builtin_prefetch(&order[drawn[next & (k_lead - 1)]], 1);
            }
            std::swap(order[i], order[drawn[i & (k_lead - 1)]]);
        }
        return;
    }
#endif
    std::shuffle(order.begin(), order.end(), rng);
}

Candidates candidates(const SurfaceView& m, std::span<const uint32_t> triangles, float density, std::mt19937& rng) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    Candidates out;
    double expected_total = 0.0;
    for (uint32_t t : triangles) {
        const auto& tri = m.triangles[t];
        const Vec3f& a = m.positions[tri[0]];
        expected_total += 0.5 * double((m.positions[tri[1]] - a).cross(m.positions[tri[2]] - a).norm()) * density + 1.0;
    }
    out.all.reserve(size_t(std::min(expected_total, 1e9)));
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
            out.all.push_back({t, Vec2f(r1, r2)});
        }
    }
    out.order.resize(out.all.size());
    for (uint32_t i = 0; i < out.order.size(); ++i) out.order[i] = i;
    shuffle_order(out.order, rng);
    return out;
}

Vec3f position_of(const SurfaceView& m, uint32_t t, const Vec2f& b) {
    const auto& tri = m.triangles[t];
    return (1.0f - b.x() - b.y()) * m.positions[tri[0]] + b.x() * m.positions[tri[1]] + b.y() * m.positions[tri[2]];
}

// Candidates are read in shuffled order, each a cache miss: asked for this many ahead, the
// memory has them by the time they are tried.
constexpr size_t k_ahead = 16;
inline void prefetch(const Candidates& cands, size_t i) {
    if (i < cands.order.size()) __builtin_prefetch(&cands.all[cands.order[i]]);
}

// `piece`, when not empty, is the piece of each triangle: a candidate is blocked only by points
// of its own piece. At the moment of a cut both sides of it coincide, and a gap on one side
// must not count as covered by the other side's samples, which leave with the other piece.
class Acceptor {
public:
    static constexpr size_t k_blockers_kept = 4;
    Acceptor(const SurfaceView& m, std::span<const uint32_t> piece, PointGrid& grid, BoundaryParticles& out)
        : m_(m), piece_(piece), grid_(grid), out_(out) {}

    // Candidate `c`, tried in turn: kept when no point lies within h of it. With `remember`, the
    // test asks the triangle's last blockers first (worth its memory for many darts).
    void try_one(const Candidate& c, bool remember) {
        const Vec3f p = position(c);
        if (!remember) return try_at(c, p);
        if (last_blocker_.empty()) last_blocker_.assign(k_blockers_kept * m_.triangles.size(), PointGrid::k_none);
        if (!blocked(c, p)) add(c, p);
    }

    // Candidates [begin, end) of `order`, tried in turn with the same outcome as try_one on
    // each, the grid's test shared among threads: points are only ever added, so a candidate
    // blocked by the grid as it stood before a batch stays blocked. The threads test a batch
    // against that grid, read-only; one thread then tries the few that passed in order against
    // the grid as it has grown. Most darts land near a sample once a few are placed.
    void try_batch(const Candidates& cands, size_t begin, size_t end, core::ThreadPool& pool) {
        const size_t n = end - begin;
        if (last_blocker_.empty()) last_blocker_.assign(k_blockers_kept * m_.triangles.size(), PointGrid::k_none);
        at_.resize(n);
        blocked_.resize(n);
        pool.parallel_for(n, [&](unsigned, size_t b, size_t e) {
            for (size_t i = b; i < e; ++i) {
                prefetch(cands, begin + i + k_ahead);
                const Candidate& c = cands.all[cands.order[begin + i]];
                at_[i] = position(c);
                blocked_[i] = blocked(c, at_[i]) ? 1 : 0;
            }
        });
        for (size_t i = 0; i < n; ++i)
            if (!blocked_[i]) try_at(cands.all[cands.order[begin + i]], at_[i]);
    }

private:
    uint32_t tag(const Candidate& c) const { return piece_.empty() ? PointGrid::k_any : piece_[c.triangle]; }
    // grid_.near(p, tag(c)), asking first the points that last blocked darts on c's triangle:
    // a triangle is about h across, so a few samples block all its darts, and a point tested
    // saves the cells' lookups (three dependent cache misses a cell). Threads testing a batch
    // share the record; whichever points it holds, the answer is the grid's. (One point refused
    // 61 % of a globe's darts; four, kept newest first, more; eight cost more than they saved.)
    bool blocked(const Candidate& c, const Vec3f& p) {
        const uint32_t t = tag(c);
        uint32_t* record = &last_blocker_[k_blockers_kept * size_t(c.triangle)];
        uint32_t known[k_blockers_kept];
        for (size_t k = 0; k < k_blockers_kept; ++k) {
            known[k] = std::atomic_ref<uint32_t>(record[k]).load(std::memory_order_relaxed);
            if (known[k] != PointGrid::k_none && grid_.blocks(known[k], p, t)) return true;
        }
        const uint32_t found = grid_.blocker(p, t);
        if (found == PointGrid::k_none) return false;
        for (size_t k = k_blockers_kept - 1; k > 0; --k) std::atomic_ref<uint32_t>(record[k]).store(known[k - 1], std::memory_order_relaxed);
        std::atomic_ref<uint32_t>(record[0]).store(found, std::memory_order_relaxed);
        return true;
    }

    Vec3f position(const Candidate& c) const {
        const auto& tri = m_.triangles[c.triangle];
        return candidate_position(m_.positions[tri[0]], m_.positions[tri[1]], m_.positions[tri[2]], c.bary);
    }
    void try_at(const Candidate& c, const Vec3f& p) {
        if (!grid_.near(p, tag(c))) add(c, p);
    }
    void add(const Candidate& c, const Vec3f& p) {
        grid_.add(p, tag(c));
        const auto& tri = m_.triangles[c.triangle];
        const Vec3f &a = m_.positions[tri[0]], &b = m_.positions[tri[1]], &d = m_.positions[tri[2]];
        out_.triangle.push_back(c.triangle);
        out_.bary.push_back(c.bary);
        out_.position.push_back(p);
        out_.normal.push_back((b - a).cross(d - a).normalized());
    }
    const SurfaceView& m_;
    std::span<const uint32_t> piece_;
    PointGrid& grid_;
    BoundaryParticles& out_;
    std::vector<Vec3f> at_;
    std::vector<uint8_t> blocked_;
    // Per triangle of m_, the points that last blocked darts there, newest first (made for many darts).
    std::vector<uint32_t> last_blocker_;
};

// The darts of a batch that pass the read-only test are tried again in order, and the larger
// the batch, the more of them fail only against samples the same batch placed (at this size a
// 100k-triangle globe tries 104k again for the 95k it keeps, of 7.1M darts); much smaller
// batches cost a dispatch each for little work.
constexpr size_t k_batch = 16384;

void accept(const SurfaceView& m, const Candidates& cands, std::span<const uint32_t> piece, PointGrid& grid,
            BoundaryParticles& out, core::ThreadPool* pool) {
    Acceptor acceptor(m, piece, grid, out);
    const size_t n = cands.order.size();
    if (!pool || pool->size() < 2 || n < 4 * k_batch) {
        for (size_t i = 0; i < n; ++i) {
            prefetch(cands, i + k_ahead);
            acceptor.try_one(cands.all[cands.order[i]], n >= k_batch);
        }
        return;
    }
    for (size_t begin = 0; begin < n; begin += k_batch) acceptor.try_batch(cands, begin, std::min(n, begin + k_batch), *pool);
}

} // namespace

void BoundaryParticles::clear() {
    triangle.clear();
    bary.clear();
    offset.clear();
    local_normal.clear();
    position.clear();
    normal.clear();
    fade.clear();
    fade_step.clear();
    size_factor.clear();
    color.clear();
    texcoord.clear();
    thin_level.clear();
    triangle_growth.clear();
    thin_gaps.clear();
}

float spacing(const mesh::TriangleMesh& m, float eta) { return eta * mesh::mean_edge_length(m); }

float spacing_for_budget(const mesh::TriangleMesh& m, size_t budget) {
    if (budget == 0) return 0.0f;
    double area = 0.0;
    for (const mesh::Triangle& t : m.triangles)
        area += 0.5 * double((m.positions[t[1]] - m.positions[t[0]]).cross(m.positions[t[2]] - m.positions[t[0]]).norm());
    return area > 0.0 && std::isfinite(area) ? float(std::sqrt(area / (double(k_area_per_sample) * double(budget)))) : 0.0f;
}

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

namespace {
// Blocks candidates within h of the anchors and of the samples already placed, over the box
// around `triangles` (a local refill stays local), then throws darts.
void fill(const SurfaceView& m, std::span<const Vec3f> anchors, std::span<const uint32_t> triangles,
          std::span<const uint32_t> piece, const SamplingOptions& o, BoundaryParticles& samples,
          core::ThreadPool* pool = nullptr) {
    PBDSPLAT_ASSERT(o.h > 0.0f && std::isfinite(o.h), "boundary particle spacing h must be positive");
    Eigen::AlignedBox3f near;
    for (uint32_t t : triangles)
        for (uint32_t v : m.triangles[t]) near.extend(m.positions[v]);
    if (near.isEmpty()) return;
    near.min().array() -= o.h;
    near.max().array() += o.h;
    PointGrid grid(o.h, triangles.size() == m.triangles.size() ? anchors.size() + samples.size() + 1024 : 1024);
    // Anchors are the mesh's vertices (or none): a vertex's piece is that of any triangle using it.
    std::vector<uint32_t> piece_of_vertex;
    if (!piece.empty() && !anchors.empty()) {
        piece_of_vertex.assign(anchors.size(), PointGrid::k_any);
        for (size_t t = 0; t < m.triangles.size(); ++t)
            for (uint32_t v : m.triangles[t])
                if (v < anchors.size()) piece_of_vertex[v] = piece[t];
    }
    for (size_t v = 0; v < anchors.size(); ++v)
        if (near.contains(anchors[v])) grid.add(anchors[v], piece_of_vertex.empty() ? PointGrid::k_any : piece_of_vertex[v]);
    for (size_t i = 0; i < samples.size(); ++i) {
        const Vec3f p = position_of(m, samples.triangle[i], samples.bary[i]);
        if (near.contains(p)) grid.add(p, piece.empty() ? PointGrid::k_any : piece[samples.triangle[i]]);
    }
    std::mt19937 rng(o.seed);
    accept(m, candidates(m, triangles, o.candidates / (o.h * o.h), rng), piece, grid, samples, pool);
}

} // namespace

// New samples on an embedded surface take the embedding of their triangle's nearest samples
// (the fine surface's height over the coarse triangle there).
void embed_appended(size_t first, BoundaryParticles& s) {
    if (!s.embedded() || first >= s.size()) return;
    // Only the old samples on the new ones' triangles matter: picked with one flag per
    // triangle in a pass over the samples, not by sorting them all.
    uint32_t top = 0;
    for (size_t i = first; i < s.size(); ++i) top = std::max(top, s.triangle[i]);
    std::vector<uint8_t> wanted(size_t(top) + 1, 0);
    for (size_t i = first; i < s.size(); ++i) wanted[s.triangle[i]] = 1;
    std::vector<std::pair<uint32_t, uint32_t>> by_triangle;  // (triangle, sample) of the old ones
    for (size_t i = 0; i < first; ++i)
        if (s.triangle[i] <= top && wanted[s.triangle[i]]) by_triangle.emplace_back(s.triangle[i], uint32_t(i));
    std::sort(by_triangle.begin(), by_triangle.end());
    s.offset.resize(s.size(), 0.0f);
    s.local_normal.resize(s.size(), Vec3f::UnitZ());
    std::vector<uint32_t> same;
    for (size_t i = first; i < s.size(); ++i) {
        auto lo = std::lower_bound(by_triangle.begin(), by_triangle.end(), std::make_pair(s.triangle[i], 0u));
        same.clear();
        for (; lo != by_triangle.end() && lo->first == s.triangle[i]; ++lo) same.push_back(lo->second);
        interpolate_embedding(s, same, s.bary[i], s.offset[i], s.local_normal[i]);
    }
}

void fill_triangles(std::span<const Vec3f> positions, std::span<const mesh::Triangle> all_triangles,
                    std::span<const uint32_t> triangles, const SamplingOptions& o, BoundaryParticles& samples) {
    fill_triangles(positions, all_triangles, triangles, positions, {}, o, samples);
}

void fill_triangles(std::span<const Vec3f> positions, std::span<const mesh::Triangle> all_triangles,
                    std::span<const uint32_t> triangles, std::span<const Vec3f> anchors, std::span<const uint32_t> piece,
                    const SamplingOptions& o, BoundaryParticles& samples) {
    const size_t first = samples.size();
    fill({positions, all_triangles}, anchors, triangles, piece, o, samples);
    embed_appended(first, samples);
}

std::vector<SurfacePoint> sample_points(const mesh::TriangleMesh& surface, std::span<const Vec3f> anchors,
                                        const SamplingOptions& o, core::ThreadPool* pool) {
    std::vector<uint32_t> all(surface.triangles.size());
    for (uint32_t t = 0; t < all.size(); ++t) all[t] = t;
    BoundaryParticles s;
    fill({surface.positions, surface.triangles}, anchors, all, {}, o, s, pool);
    const std::vector<Vec3f> vn = mesh::vertex_normals(surface);
    std::vector<SurfacePoint> out(s.size());
    for (size_t i = 0; i < s.size(); ++i) {
        const auto& t = surface.triangles[s.triangle[i]];
        const float b1 = s.bary[i].x(), b2 = s.bary[i].y(), b0 = 1.0f - b1 - b2;
        const Vec3f n = b0 * vn[t[0]] + b1 * vn[t[1]] + b2 * vn[t[2]];
        out[i] = {s.position[i], n.norm() > 0.0f ? Vec3f(n.normalized()) : s.normal[i]};
    }
    return out;
}

Mat3f triangle_frame(const Vec3f& a, const Vec3f& b, const Vec3f& c) {
    Mat3f f;
    const Vec3f e1 = b - a, n = e1.cross(c - a);
    const float le = e1.norm(), ln = n.norm();
    if (!(le > 0.0f) || !(ln > 0.0f)) return Mat3f::Identity();  // degenerate: no rotation known
    f.col(0) = e1 / le;
    f.col(2) = n / ln;
    f.col(1) = f.col(2).cross(f.col(0));
    return f;
}

namespace {
// surface_frame from the edge's direction (any length) and the interpolated normal.
Mat3f frame_about(const Vec3f& edge, const Vec3f& normal) {
    const float ln = normal.norm();
    if (!(ln > 0.0f)) return Mat3f::Zero();
    const Vec3f n = normal / ln;
    const Vec3f t = edge - edge.dot(n) * n;
    const float lt = t.norm();
    if (!(lt > 1e-6f * edge.norm())) return Mat3f::Zero();
    Mat3f f;
    f.col(0) = t / lt;
    f.col(1) = n.cross(f.col(0));
    f.col(2) = n;
    return f;
}
} // namespace

Mat3f surface_frame(const Vec3f& a, const Vec3f& b, const Vec3f& c, const Vec3f& normal) {
    const Mat3f f = frame_about(b - a, normal);
    return f.col(2).isZero() ? triangle_frame(a, b, c) : f;
}

// Below this many samples handing ranges to threads costs more than it saves.
constexpr size_t k_parallel_carry = 8192;

void update_boundary_particles(std::span<const mesh::Triangle> triangles, std::span<const Vec4f> x,
                               std::span<const Vec3f> n, BoundaryParticles& s, size_t first, core::ThreadPool* pool,
                               std::span<const uint8_t> moved) {
    const size_t count = s.size();
    s.position.resize(count);
    s.normal.resize(count);
    const uint32_t* tri_index = s.triangle.data();
    const Vec2f* bary = s.bary.data();
    const bool embedded = s.embedded();
    const auto carry = [&](size_t begin, size_t end) {
        if (embedded) {
            const float* d = s.offset.data();
            const Vec3f* ln = s.local_normal.data();
            // Each sample's normal in the frame of the interpolated normal at it (surface_frame), so
            // the frame is per sample, not per triangle.
            for (size_t i = begin; i < end; ++i) {
                if (!moved.empty() && !moved[tri_index[i]]) continue;
                const auto& t = triangles[tri_index[i]];
                const float b1 = bary[i].x(), b2 = bary[i].y(), b0 = 1.0f - b1 - b2;
                const Vec3f interpolated = b0 * n[t[0]] + b1 * n[t[1]] + b2 * n[t[2]];
                s.position[i] = (b0 * x[t[0]] + b1 * x[t[1]] + b2 * x[t[2]]).head<3>() + d[i] * interpolated;
                s.normal[i] = surface_frame(x[t[0]].head<3>(), x[t[1]].head<3>(), x[t[2]].head<3>(), interpolated) * ln[i];
            }
            return;
        }
        for (size_t i = begin; i < end; ++i) {
            if (!moved.empty() && !moved[tri_index[i]]) continue;
            const auto& t = triangles[tri_index[i]];
            const float b1 = bary[i].x(), b2 = bary[i].y(), b0 = 1.0f - b1 - b2;
            const Vec4f p = b0 * x[t[0]] + b1 * x[t[1]] + b2 * x[t[2]];
            s.position[i] = p.head<3>();
            const Vec3f nn = b0 * n[t[0]] + b1 * n[t[1]] + b2 * n[t[2]];
            const float len = nn.norm();
            s.normal[i] = len > 0.0f ? Vec3f(nn / len) : n[t[0]];
        }
    };
    const size_t todo = count > first ? count - first : 0;
    if (pool && pool->size() > 1 && todo >= k_parallel_carry)
        pool->parallel_for(todo, [&](unsigned, size_t b, size_t e) { carry(first + b, first + e); });
    else carry(first, count);
}

void update_boundary_positions(std::span<const mesh::Triangle> triangles, std::span<const Vec4f> x, std::span<const Vec3f> n,
                               BoundaryParticles& s) {
    const size_t count = s.size();
    s.position.resize(count);
    const bool embedded = s.embedded();
    for (size_t i = 0; i < count; ++i) {
        const auto& t = triangles[s.triangle[i]];
        const float b1 = s.bary[i].x(), b2 = s.bary[i].y(), b0 = 1.0f - b1 - b2;
        Vec3f p = (b0 * x[t[0]] + b1 * x[t[1]] + b2 * x[t[2]]).head<3>();
        if (embedded) p += s.offset[i] * (b0 * n[t[0]] + b1 * n[t[1]] + b2 * n[t[2]]);
        s.position[i] = p;
    }
}

} // namespace pbdsplat::surface
