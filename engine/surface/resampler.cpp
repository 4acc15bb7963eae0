#include "surface/resampler.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "core/assert.h"
#include "mesh/deformation.h"
#include "surface/embedding.h"
#include "surface/point_grid.h"

namespace pbdsplat::surface {
// Named, not anonymous: Resampler::Impl holds a LocalPoints, and a unity build puts this file in
// a unit whose main file is another (GCC's subobject-linkage warning).
namespace resampler_parts {

// SplitMix64: a 64-bit counter through a mixing function; plenty for throwing darts.
struct SplitMix {
    uint64_t state;
    static uint64_t mix(uint64_t z) {
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    uint32_t next() { return uint32_t(mix(state += 0x9E3779B97F4A7C15ull) >> 32); }
    // Two numbers in [0, 1) for draw k of a stream keyed by `key`, from one mix: any draw without
    // the ones before it, so a draw that is not needed is not made.
    static void unit_pair(uint64_t key, uint64_t k, float& u, float& v) {
        const uint64_t z = mix(key + (k + 1) * 0x9E3779B97F4A7C15ull);
        u = float(uint32_t(z >> 40)) * (1.0f / 16777216.0f);
        v = float(uint32_t(z >> 8) & 0xFFFFFFu) * (1.0f / 16777216.0f);
    }
};

// A few dozen points tested by brute force: for the one-ring of a triangle, cheaper than any
// hash (no table to clear, no cell lookups), and a test that stops at the first point near
// enough usually stops among the first few (the triangle's own samples come first).
class LocalPoints {
public:
    void clear() { blocks_.clear(), size_ = 0; }
    void add(const Vec3f& p) {
        if (size_ % 4 == 0) blocks_.push_back(Block{});  // padded far away: a miss
        Block& b = blocks_.back();
        const size_t k = size_ % 4;
        b.x[k] = p.x(), b.y[k] = p.y(), b.z[k] = p.z();
        ++size_;
    }
    // Any point nearer than sqrt(r2) to p: four at a time (one SSE compare each), stopping at
    // the first block with a hit. In intrinsics: Eigen's any() of a comparison stops at the
    // first true lane, and gcc built that as four scalar distances with a branch each (a third
    // of the darts' instructions on balloon_inflate).
    bool near(const Vec3f& p, float r2) const {
#if defined(__SSE2__)
        return near(_mm_setr_ps(p.x(), p.y(), p.z(), 0.0f), r2);
#else
        for (const Block& b : blocks_) {
            const Eigen::Array4f dx = b.x - p.x(), dy = b.y - p.y(), dz = b.z - p.z();
            if (((dx * dx + dy * dy + dz * dz) < r2).any()) return true;
        }
        return false;
#endif
    }
#if defined(__SSE2__)
    // The same for a point in lanes x, y, z (the fourth ignored).
    bool near(__m128 p, float r2) const {
        const __m128 px = _mm_shuffle_ps(p, p, 0x00), py = _mm_shuffle_ps(p, p, 0x55), pz = _mm_shuffle_ps(p, p, 0xAA), v_r2 = _mm_set1_ps(r2);
        for (const Block& b : blocks_) {
            const __m128 dx = _mm_sub_ps(_mm_load_ps(b.x.data()), px), dy = _mm_sub_ps(_mm_load_ps(b.y.data()), py);
            const __m128 dz = _mm_sub_ps(_mm_load_ps(b.z.data()), pz);
            const __m128 d2 = _mm_add_ps(_mm_add_ps(_mm_mul_ps(dx, dx), _mm_mul_ps(dy, dy)), _mm_mul_ps(dz, dz));
            if (_mm_movemask_ps(_mm_cmplt_ps(d2, v_r2)) != 0) return true;
        }
        return false;
    }
#endif

private:
    struct Block {
        Eigen::Array4f x = Eigen::Array4f::Constant(1e18f), y = Eigen::Array4f::Constant(1e18f), z = Eigen::Array4f::Constant(1e18f);
    };
    std::vector<Block> blocks_;
    size_t size_ = 0;
};

} // namespace resampler_parts
using resampler_parts::LocalPoints;
using resampler_parts::SplitMix;

class Resampler::Impl {
public:
    Impl(const Inputs& in, const DensityOptions& o, BoundaryParticles& s, DensityStats& stats)
        : in_(in), o_(o), s_(s), stats_(stats),
          by_triangle_(make_rows(in.triangles.size(), s.size(), [&](size_t i) { return s.triangle[i]; })),
          ring_(in.ring),
          mark_(in.triangles.size(), 0), vertex_mark_(in.anchors_drawn ? in.x.size() : 0, 0), step_(1.0f / float(std::max(1u, o.fade_frames))), embedded_(s.embedded()),
          fresh_(o.insert_spacing * in.h, 256), fresh_head_(in.triangles.size(), k_none), first_new_(uint32_t(s.size())) {
        s.pad_fades();
    }

    // What a dart into t is tested against: the triangle's own samples first (most darts land
    // near one of them), then its one-ring's, this frame's new ones and the drawn particles there,
    // those farther than keep2 from t's centre left out (they can reject no dart).
    void gather_local(uint32_t t, const Vec3f& centre, float keep2) {
        auto offer = [&](const Vec3f& q) {
            if ((q - centre).squaredNorm() < keep2) local_.add(q);
        };
        local_.clear();
        for (uint32_t i : same_)
            if (!s_.retiring(i)) local_.add(s_.position[i]);
        around(t, [&](uint32_t n) {
            if (n != t)
                for (uint32_t i : by_triangle_[n])
                    if (!s_.retiring(i)) offer(s_.position[i]);
            for (uint32_t i = fresh_head_[n]; i != k_none; i = fresh_next_[i - first_new_]) offer(s_.position[i]);
            if (in_.anchors_drawn) each_new_corner(n, [&](uint32_t v) { offer(in_.x[v].head<3>()); });
        });
    }

    // Stratified darts: the triangle cut into cells x cells sub-triangles, one dart in each,
    // visited in a scrambled order (a stride through the cells from a random start). A gap the
    // size of a cell cannot be missed, where independent darts need several times as many
    // throws to find the same gaps. `expected`: the darts the triangle's area asks for.
    struct CellWalk {
        uint32_t cells, start, stride;
        uint64_t key;  // each cell's dart from its own draw of the triangle's stream
    };
    CellWalk cell_walk(uint32_t t, float expected) const {
        // A generator per triangle and frame, seeded in a few instructions: a Mersenne twister
        // seeded its 624 words for every resampled triangle (a fifth of balloon_inflate's run).
        SplitMix rng{(uint64_t(in_.seed) << 32) ^ (in_.frame * 0x9E3779B97F4A7C15ull) ^ (uint64_t(t) * 0xD1B54A32D192ED03ull)};
        CellWalk w;
        w.cells = std::clamp(uint32_t(std::lround(std::sqrt(expected))), 1u, 64u);
        const uint32_t n = w.cells * w.cells;
        w.start = rng.next() % n;
        uint32_t stride = 1 + 2 * (rng.next() % std::max(1u, n / 2));  // odd; coprime with n below
        while (std::gcd(stride, n) != 1) stride += 2;
        w.stride = stride % n;
        w.key = uint64_t(rng.next()) << 32 | rng.next();
        return w;
    }

    // Barycentric (b1, b2) of the dart into cell `id` (its row entry `row`: i << 8 | m) of
    // cells x cells (1 / cells: `inv_cells`). Upright cells span (i, j), (i + 1, j), (i, j + 1);
    // inverted ones the mirror image from (i + 1, j + 1).
    static Vec2f dart_in(uint16_t row, uint64_t key, uint32_t id, float inv_cells) {
        const uint32_t i = row >> 8, m = row & 0xFFu, j = m / 2;
        float u, v;
        SplitMix::unit_pair(key, id, u, v);
        if (u + v > 1.0f) u = 1.0f - u, v = 1.0f - v;
        const bool inverted = m % 2 == 1;
        return {(inverted ? float(i + 1) - u : float(i) + u) * inv_cells, (inverted ? float(j + 1) - v : float(j) + v) * inv_cells};
    }

    // The triangle's samples (same_), their neighbours for the offsets where the samples are
    // embedded, and what a dart is tested against (gather_local). Every dart lies within `bound`
    // of the centre (the farthest corner, plus the offset: a new sample's offset blends its
    // neighbours'): a point farther than bound + r can reject none, and stays out of the list.
    // The one-ring of a coarse triangle carrying many samples holds several times what borders
    // it (the bunny: a dart that stays was tested against some 220 points).
    void prepare_local(uint32_t t, const Vec3f& a, const Vec3f& b, const Vec3f& c, float r) {
        same_.assign(by_triangle_[t].begin(), by_triangle_[t].end());
        float reach = 0.0f;
        if (embedded_) {
            for (uint32_t i : same_) reach = std::max(reach, std::abs(s_.offset[i]));
            neighbours_.assign(s_, same_);
        }
        const Vec3f centre = (a + b + c) / 3.0f;
        const float bound = std::sqrt(std::max({(a - centre).squaredNorm(), (b - centre).squaredNorm(), (c - centre).squaredNorm()})) + reach;
        gather_local(t, centre, (bound + r) * (bound + r));
    }

    // A dart that stays: a new sample of triangle (a, b, c) = t, fading in.
    void add_sample(uint32_t t, const Vec3f& p, const Vec2f& bary, float d, const Vec3f& local, const Vec3f& interpolated, const Vec3f& a,
                    const Vec3f& b, const Vec3f& c) {
        fresh_.add(p);
        local_.add(p);
        const uint32_t index = uint32_t(s_.size());
        fresh_next_.push_back(fresh_head_[t]);
        fresh_head_[t] = index;
        s_.triangle.push_back(t);
        s_.bary.push_back(bary);
        if (embedded_) s_.offset.push_back(d), s_.local_normal.push_back(local);
        s_.position.push_back(p);
        const float len = interpolated.norm();
        s_.normal.push_back(embedded_ ? Vec3f(surface_frame(a, b, c, interpolated) * local)
                                      : len > 0.0f ? Vec3f(interpolated / len) : Vec3f(triangle_frame(a, b, c).col(2)));
        s_.fade.push_back(0.0f);
        s_.fade_step.push_back(step_);
        ++stats_.inserted;
    }

    // New samples darted into t where none lies within insert_spacing h. A dart is tested against
    // the one-ring's samples (this frame's new ones included) in a flat list, the rest of the
    // frame's new ones in a grid: a hash grid rebuilt per triangle cost 27 lookups a dart and the
    // clearing of its table. The normal and the offset are made only where the samples stand off
    // the triangle, or for a dart that stays: most are rejected.
    void insert(uint32_t t) {
        const auto& tri = in_.triangles[t];
        const Vec3f a = in_.x[tri[0]].head<3>(), b = in_.x[tri[1]].head<3>(), c = in_.x[tri[2]].head<3>();
        const float r = o_.insert_spacing * in_.h, r2 = r * r;
        prepare_local(t, a, b, c, r);
        const float area = 0.5f * (b - a).cross(c - a).norm();
        const CellWalk walk = cell_walk(t, area * o_.candidates / (in_.h * in_.h));
        const uint32_t cells = walk.cells, n = cells * cells;
        uint32_t cell = walk.start;
        const float inv_cells = 1.0f / float(cells);
        const Vec3f &na = in_.normals[tri[0]], &nb = in_.normals[tri[1]], &nc = in_.normals[tri[2]];
        const uint16_t* rows = cell_rows(cells);
#if defined(__SSE2__)
        const __m128 lane_a = _mm_loadu_ps(in_.x[tri[0]].data()), lane_b = _mm_loadu_ps(in_.x[tri[1]].data()),
                     lane_c = _mm_loadu_ps(in_.x[tri[2]].data());
#endif
        for (uint32_t k = 0; k < n; ++k) {
            const uint32_t id = cell;
            cell += walk.stride;
            if (cell >= n) cell -= n;
            const Vec2f dart = dart_in(rows[id], walk.key, id, inv_cells);
            const float b1 = dart.x(), b2 = dart.y(), b0 = 1.0f - b1 - b2;
#if defined(__SSE2__)
            // Off the embedding, the dart in lanes first, the same sums in the same order: a
            // rejected dart (most) never leaves them, nor sets up anything else.
            __m128 lanes_p = _mm_setzero_ps();
            if (!embedded_) {
                lanes_p = _mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_set1_ps(b0), lane_a), _mm_mul_ps(_mm_set1_ps(b1), lane_b)),
                                     _mm_mul_ps(_mm_set1_ps(b2), lane_c));
                if (local_.near(lanes_p, r2)) continue;
            }
#endif
            Vec3f p;
            float d = 0.0f;
            Vec3f local = Vec3f::UnitZ(), interpolated = Vec3f::Zero();
            if (embedded_) {
                p = b0 * a + b1 * b + b2 * c;
                interpolate_embedding(neighbours_, Vec2f(b1, b2), d, local);
                interpolated = b0 * na + b1 * nb + b2 * nc;
                p += d * interpolated;
                if (local_.near(p, r2)) continue;
            } else {
#if defined(__SSE2__)
                alignas(16) float out[4];
                _mm_store_ps(out, lanes_p);
                p = Vec3f(out[0], out[1], out[2]);
#else
                p = b0 * a + b1 * b + b2 * c;
                if (local_.near(p, r2)) continue;
#endif
            }
            if (fresh_.near(p)) continue;
            if (in_.max_samples && s_.size() >= in_.max_samples) {
                stats_.capped = true;
                break;
            }
            if (!embedded_) interpolated = b0 * na + b1 * nb + b2 * nc;
            add_sample(t, p, Vec2f(b1, b2), d, local, interpolated, a, b, c);
        }
    }

    void retire(uint32_t t) {
        local_.clear();
        around(t, [&](uint32_t n) {
            if (n != t)
                for (uint32_t i : by_triangle_[n])
                    if (!s_.retiring(i)) local_.add(s_.position[i]);
            if (in_.anchors_drawn) each_new_corner(n, [&](uint32_t v) { local_.add(in_.x[v].head<3>()); });
        });
        const float r2 = (o_.retire_spacing * in_.h) * (o_.retire_spacing * in_.h);
        for (uint32_t i : by_triangle_[t]) {
            if (s_.retiring(i) || s_.on_edge(i)) continue;  // edge samples follow the boundary (surface/edges.h)
            if (local_.near(s_.position[i], r2)) {
                s_.fade_step[i] = -step_;
                ++stats_.retired;
            } else {
                local_.add(s_.position[i]);
            }
        }
    }

private:
    // Per cell of a triangle cut into `cells` x `cells`: its row i (along b1) in the high byte
    // and its place m in the row in the low one. Row i holds 2 (cells - i) - 1 cells, upright
    // (m even) and inverted alternately. Kept per size: finding the row by walking them was a
    // tenth of a dart.
    const uint16_t* cell_rows(uint32_t cells) {
        std::vector<uint16_t>& rows = cell_rows_[cells];
        if (rows.empty())
            for (uint32_t i = 0; i < cells; ++i)
                for (uint32_t m = 0; m < 2 * (cells - i) - 1; ++m) rows.push_back(uint16_t(i << 8 | m));
        return rows.data();
    }

    // The triangles sharing a vertex with t (t included), each once per call.
    template <class Visit>
    void around(uint32_t t, Visit&& visit) {
        ++stamp_;
        for (uint32_t v : in_.triangles[t])
            for (uint32_t c : ring_[v]) {
                const uint32_t n = c / 3;
                if (mark_[n] == stamp_) continue;
                mark_[n] = stamp_;
                visit(n);
            }
    }

    // Within a call of around(): each corner of triangle n not met yet in this call. A vertex is
    // a corner of some six triangles of the ring: offered once, not three times (39 offers a
    // resampling on balloon_inflate for some 13 vertices, each a point more for every dart).
    template <class Visit>
    void each_new_corner(uint32_t n, Visit&& visit) {
        for (uint32_t v : in_.triangles[n]) {
            if (vertex_mark_[v] == stamp_) continue;
            vertex_mark_[v] = stamp_;
            visit(v);
        }
    }

    Inputs in_;
    const DensityOptions& o_;
    BoundaryParticles& s_;
    DensityStats& stats_;
    Rows by_triangle_;
    const Rows& ring_;
    std::vector<uint32_t> mark_, vertex_mark_;  // stamped per call of around()
    uint32_t stamp_ = 0;
    float step_;
    bool embedded_;
    std::vector<uint32_t> same_;
    std::array<std::vector<uint16_t>, 65> cell_rows_;  // by cells (1 to 64)
    EmbeddedNeighbours neighbours_;  // same_'s embeddings, for the darts' interpolation
    LocalPoints local_;  // the samples around the triangle at hand
    PointGrid fresh_;    // every sample inserted this frame
    // The frame's new samples by triangle: a chain through fresh_next_ (indexed from first_new_).
    static constexpr uint32_t k_none = ~0u;
    std::vector<uint32_t> fresh_head_, fresh_next_;
    uint32_t first_new_;
};


Resampler::Resampler(const Inputs& in, const DensityOptions& o, BoundaryParticles& s, DensityStats& stats)
    : impl_(std::make_unique<Impl>(in, o, s, stats)) {}
Resampler::~Resampler() = default;
void Resampler::insert(uint32_t t) { impl_->insert(t); }
void Resampler::retire(uint32_t t) { impl_->retire(t); }

} // namespace pbdsplat::surface
