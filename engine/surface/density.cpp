#include "surface/density.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "core/assert.h"
#include "mesh/deformation.h"
#include "surface/crowding.h"
#include "surface/embedding.h"
#include "surface/point_grid.h"
#include "surface/rows.h"
#include "surface/stretch_scan.h"

namespace pbdsplat::surface {
namespace {

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

// inverse_rest_lanes_'s size: four entries per triangle, in whole blocks of four triangles.
size_t lane_floats(size_t triangles) { return 16 * ((triangles + 3) / 4); }

} // namespace

DensityControl::DensityControl(std::span<const Vec3f> rest, std::span<const mesh::Triangle> triangles, const DensityOptions& o)
    : options_(o) {
    inverse_rest_.resize(triangles.size());
    inverse_rest_lanes_.assign(lane_floats(triangles.size()), 0.0f);
    for (uint32_t t = 0; t < triangles.size(); ++t) set_rest(rest, triangles, t);
    stretch2_.assign(triangles.size(), 1.0f);
    squeeze2_.assign(triangles.size(), 1.0f);
    reference2_.assign(triangles.size(), 1.0f);
    reference_squeeze2_.assign(triangles.size(), 1.0f);
    beyond_.assign(triangles.size(), 0);
    // A fresh maximal sampling has neither crowds nor gaps: the samples' trigger waits for a change.
    changed_.assign(triangles.size(), 0);
    shrank_large2_.resize(triangles.size());
    shrank_small2_.resize(triangles.size());
    grew_large2_.resize(triangles.size());
    grew_small2_.resize(triangles.size());
    for (uint32_t t = 0; t < triangles.size(); ++t) arm_change_bounds(t);
}

namespace {
constexpr float k_changed = 0.05f;  // the change (in stretch) that calls the samples' trigger
constexpr float k_shrank2 = (1.0f - k_changed) * (1.0f - k_changed), k_grew2 = (1.0f + k_changed) * (1.0f + k_changed);
} // namespace

void DensityControl::arm_change_bounds(uint32_t t) {
    shrank_large2_[t] = k_shrank2 * stretch2_[t];
    shrank_small2_[t] = k_shrank2 * squeeze2_[t];
    grew_large2_[t] = k_grew2 * stretch2_[t];
    grew_small2_[t] = k_grew2 * squeeze2_[t];
}

void DensityControl::disarm_change_bounds(uint32_t t) {
    // Squared stretches are >= 0 and finite (or NaN, which compares false): these never trigger.
    if (changed_[t] & k_shrank) shrank_large2_[t] = shrank_small2_[t] = -1.0f;
    if (changed_[t] & k_grew) grew_large2_[t] = grew_small2_[t] = std::numeric_limits<float>::infinity();
}

void DensityControl::set_rest(std::span<const Vec3f> rest, std::span<const mesh::Triangle> triangles, uint32_t t) {
    // A sliver (zero inverse) is never resampled: its neighbours cover it.
    inverse_rest_[t] = mesh::rest_frame_inverse(rest[triangles[t][0]], rest[triangles[t][1]], rest[triangles[t][2]]);
    float* block = inverse_rest_lanes_.data() + 16 * (t / 4);
    for (int e = 0; e < 4; ++e) block[4 * e + t % 4] = inverse_rest_[t].data()[e];
}

void DensityControl::topology_changed(std::span<const Vec3f> rest, std::span<const mesh::Triangle> triangles,
                                      std::span<const uint32_t> touched) {
    inverse_rest_.resize(triangles.size(), Eigen::Matrix2f::Zero());
    inverse_rest_lanes_.resize(lane_floats(triangles.size()), 0.0f);  // zero, as the new inverses
    stretch2_.resize(triangles.size(), 1.0f);
    squeeze2_.resize(triangles.size(), 1.0f);
    reference2_.resize(triangles.size(), 1.0f);
    reference_squeeze2_.resize(triangles.size(), 1.0f);
    beyond_.resize(triangles.size(), 0);
    const size_t before = changed_.size();
    changed_.resize(triangles.size(), 1);
    shrank_large2_.resize(triangles.size());
    shrank_small2_.resize(triangles.size());
    grew_large2_.resize(triangles.size());
    grew_small2_.resize(triangles.size());
    for (size_t t = before; t < triangles.size(); ++t) arm_change_bounds(uint32_t(t)), disarm_change_bounds(uint32_t(t));
    check_due_ = true;
    check_wait_ = 0;  // a changed topology is checked once the settle frames since the last check have passed
    ring_.start.clear();
    // A touched triangle was refilled from its rest shape: its samples stand for stretch 1.
    for (uint32_t t : touched) {
        set_rest(rest, triangles, t);
        reference2_[t] = 1.0f;
        reference_squeeze2_[t] = 1.0f;
        beyond_[t] = 0;
        changed_[t] = k_shrank | k_grew;
        disarm_change_bounds(t);
    }
}

namespace {
// One frame's resampling of the due triangles: new samples darted where a triangle stretched
// (kept insert_spacing h from every sample around it), fade-outs where one shrank (samples
// closer than retire_spacing h to a kept one).
class Resampler {
public:
    struct Inputs {
        std::span<const Vec4f> x;
        std::span<const Vec3f> normals;
        std::span<const mesh::Triangle> triangles;
        const Rows& ring;  // the triangles around each particle
        bool anchors_drawn;
        float h;
        uint32_t seed;
        uint64_t frame;
        size_t max_samples;
    };
    Resampler(const Inputs& in, const DensityOptions& o, BoundaryParticles& s, DensityStats& stats)
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

} // namespace

const Rows& DensityControl::ring(size_t particles, std::span<const mesh::Triangle> triangles) {
    // Kept from frame to frame: only a topology change (which clears it) changes it.
    if (ring_.start.size() != particles + 1 || ring_.items.size() != 3 * triangles.size()) ring_ = corner_rows(particles, triangles);
    return ring_;
}

void DensityControl::judge(uint32_t t, const Thresholds& th, std::vector<Due>& work) {
    // A sliver (zero inverse: zero stretches) keeps its reference: never due, never changed.
    if (stretch2_[t] == 0.0f && inverse_rest_[t].isZero()) return;
    const float l2 = stretch2_[t], s2 = squeeze2_[t];
    const uint8_t was = changed_[t];
    uint8_t now = was;
    if (l2 < shrank_large2_[t] || s2 < shrank_small2_[t]) now |= k_shrank;
    if (l2 > grew_large2_[t] || s2 > grew_small2_[t]) now |= k_grew;
    if (now != was) changed_[t] = now, check_due_ = true, disarm_change_bounds(t);
    const float ref2 = reference2_[t], ref_squeeze2 = std::max(reference_squeeze2_[t], 1e-12f);
    // Along its least stretched direction as well: a triangle squashed one way keeps its
    // largest stretch while its samples crowd along the other (a body landing), and when it
    // springs back the gaps open along that direction only.
    const bool grow = l2 > th.grow2 * ref2 || s2 > th.unsquash2 * ref_squeeze2;
    const bool thin = (l2 < th.shrink2 * ref2 || s2 < th.squash2 * ref_squeeze2) && s2 > 0.0f;
    int8_t& run = beyond_[t];
    if (!grow && !thin) {
        run = 0;
        return;
    }
    const int8_t side = grow ? 1 : -1;
    // Frames in a row on this side, counted up to 120 (the settle limit is at most 60).
    run = run * side > 0 ? int8_t(side * std::min(std::abs(int(run)) + 1, 120)) : side;
    if (uint32_t(std::abs(run)) < th.settle) return;
    // max(|log a|, |log b|) orders as max(a, 1/a, b, 1/b): no logarithm for each due triangle.
    const float a = l2 / ref2, b = std::max(s2 / ref_squeeze2, 1e-12f);
    const float priority = std::max({a, 1.0f / a, b, 1.0f / b});
    work.push_back({priority, t, grow, thin});
}

std::vector<DensityControl::Due> DensityControl::due_triangles(std::span<const Vec4f> x, std::span<const mesh::Triangle> triangles) {
    std::vector<Due> work;
    // Squared stretches throughout (one square root a triangle instead of three, no division):
    // this loop runs over every triangle every frame, the whole cost of a frame where nothing
    // stretches.
    const float grow2 = options_.grow * options_.grow, shrink2 = options_.shrink * options_.shrink;
    const float squash2 = options_.squash * options_.squash, unsquash2 = 1.0f / squash2;
    const uint32_t settle = std::max(1u, options_.settle_frames);
    const Thresholds th{grow2, shrink2, squash2, unsquash2, settle};
    const size_t n = triangles.size();
    size_t t = 0;
    // Most triangles in SIMD lanes (surface/stretch_scan.h): only those that changed, crossed a
    // threshold or were counting frames past one come back for the per-triangle logic (an
    // inflating body has most blocks busy, rarely every lane); a frame where nothing stretches
    // costs the scan alone.
    busy_.clear();
    StretchScan scan;
    scan.x = x;
    scan.triangles = triangles;
    scan.rest_lanes = inverse_rest_lanes_.data();
    scan.stretch2 = stretch2_.data();
    scan.squeeze2 = squeeze2_.data();
    scan.shrank_large2 = shrank_large2_.data(), scan.shrank_small2 = shrank_small2_.data();
    scan.grew_large2 = grew_large2_.data(), scan.grew_small2 = grew_small2_.data();
    scan.reference2 = reference2_.data(), scan.reference_squeeze2 = reference_squeeze2_.data();
    scan.beyond = beyond_.data();
    scan.grow2 = grow2, scan.shrink2 = shrink2, scan.squash2 = squash2, scan.unsquash2 = unsquash2;
    t = scan_stretches(scan, busy_);
    // Each triangle's logic reads and writes its own entries only: after the scan, in order, it
    // does what it did inside it.
    for (uint32_t b : busy_) judge(b, th, work);
    for (; t < n; ++t) {
        const auto& tri = triangles[t];
        const Vec3f o = x[tri[0]].head<3>();
        const mesh::Stretch sigma2 = mesh::squared_stretches(inverse_rest_[t], x[tri[1]].head<3>() - o, x[tri[2]].head<3>() - o);
        stretch2_[t] = sigma2.largest;
        squeeze2_[t] = sigma2.smallest;
        judge(uint32_t(t), th, work);
    }
    return work;
}

void DensityControl::check_crowds(std::span<const Vec4f> x, std::span<const Vec3f> normals, std::span<const mesh::Triangle> triangles,
                                  bool anchors_drawn, float h, BoundaryParticles& s, size_t room, DensityStats& stats,
                                  const std::function<void(uint32_t)>& refill) {
    const uint32_t settle = std::max(1u, options_.settle_frames);
    CrowdingQuery q;
    q.h = h;
    q.crowd = options_.crowd_spacing;
    // Embedded samples stand off the simulation triangles by their offsets: a triangle's
    // centre is no point of the surface they cover.
    q.gap = s.embedded() ? 0.0f : options_.gap_spacing;
    q.anchors_drawn = anchors_drawn;
    q.fade_step = 1.0f / float(std::max(1u, options_.fade_frames));
    q.max_retired = 4 * options_.budget;
    q.changed = changed_;
    q.ring = &ring(x.size(), triangles);
    CrowdingResult c = thin_crowds(x, normals, triangles, q, s);
    stats.checked = true;
    stats.crowded = c.retired;
    stats.retired += c.retired;
    // Refill wherever no sample reaches. Not the crowded samples' own triangles: on a surface
    // still folding, samples thrown there crowd again a few frames later (the teapot deflating:
    // 80-100 retired every 4 frames for 200 frames, against 1,300 in all without).
    for (size_t k = 0; k < c.gaps.size() && k < room; ++k) {
        if (inverse_rest_[c.gaps[k]].isZero()) continue;
        refill(c.gaps[k]);
        ++stats.gaps;
        ++stats.resampled;
    }
    for (size_t t = 0; t < changed_.size(); ++t)
        if (changed_[t]) changed_[t] = 0, arm_change_bounds(uint32_t(t));
    checked_frame_ = frame_;
    check_due_ = false;
    // A check that found nothing doubles the wait for the next, up to k_check_backoff times
    // the settle frames; one that found anything brings it back. The changes keep adding up
    // in between (changed_), so a later check still sees all of them. balloon_inflate's 42
    // checks in 240 frames found nothing (the triangles' own trigger keeps up with an even
    // inflation), a quarter of its density pass; a crumpling surface finds crowds at every
    // check and keeps the short wait.
    check_wait_ = c.retired == 0 && c.gaps.empty() ? std::min(2 * std::max(settle, check_wait_), k_check_backoff * settle) : settle;
}

DensityStats DensityControl::update(std::span<const Vec4f> x, std::span<const Vec3f> normals,
                                    std::span<const mesh::Triangle> triangles, bool anchors_drawn, float h, uint32_t seed,
                                    BoundaryParticles& s) {
    PBDSPLAT_ASSERT(triangles.size() == inverse_rest_.size(),
                    "density control: the triangle list changed size; call topology_changed() after every topology change");
    DensityStats stats;
    ++frame_;
    std::vector<Due> work = due_triangles(x, triangles);
    if (!options_.enabled) {
        stats.removed = uint32_t(advance_fades(s, &stats.fading));
        return stats;
    }
    PBDSPLAT_ASSERT(s.position.size() == s.size(), "density control: update the boundary particles' positions first");
    std::optional<Resampler> resampler;
    auto r = [&]() -> Resampler& {
        if (!resampler) resampler.emplace(Resampler::Inputs{x, normals, triangles, ring(x.size(), triangles), anchors_drawn, h, seed, frame_, max_samples_}, options_, s, stats);
        return *resampler;
    };
    auto sampled = [&](uint32_t t) {
        reference2_[t] = stretch2_[t];
        reference_squeeze2_[t] = squeeze2_[t];
        beyond_[t] = 0;
    };
    if (!work.empty()) {
        const size_t take = std::min<size_t>(work.size(), options_.budget);
        std::partial_sort(work.begin(), work.begin() + take, work.end(), [](const Due& a, const Due& b) { return a.priority > b.priority; });
        stats.pending = uint32_t(work.size() - take);
        work.resize(take);
        stats.resampled = uint32_t(take);
        for (const Due& w : work) {
            if (w.thin) r().retire(w.triangle);  // first: a grown triangle's new samples keep their distance from the kept ones
            if (w.grow) r().insert(w.triangle);
            sampled(w.triangle);
        }
    }
    // The samples' own trigger, once the triangles' work is done (its new samples are kept).
    const bool by_samples = options_.crowd_spacing > 0.0f || options_.gap_spacing > 0.0f;
    const uint32_t settle = std::max(1u, options_.settle_frames);
    if (by_samples && check_due_ && frame_ >= checked_frame_ + std::max(settle, check_wait_)) {
        // Within what the triangles' work left of the budget.
        const size_t room = options_.budget - std::min<size_t>(options_.budget, stats.resampled);
        check_crowds(x, normals, triangles, anchors_drawn, h, s, room, stats, [&](uint32_t t) {
            r().insert(t);
            sampled(t);
        });
    }
    stats.removed = uint32_t(advance_fades(s, &stats.fading));
    return stats;
}

size_t advance_fades(BoundaryParticles& s, uint32_t* fading) {
    uint32_t still = 0;
    size_t finished = 0;
    const size_t n = std::min(s.fade.size(), s.fade_step.size());
    auto advance = [&](size_t i) {
        if (s.fade_step[i] == 0.0f) return;
        s.fade[i] = std::clamp(s.fade[i] + s.fade_step[i], 0.0f, 1.0f);
        if (s.fade_step[i] > 0.0f && s.fade[i] >= 1.0f) s.fade_step[i] = 0.0f;
        else if (s.fade_step[i] < 0.0f && s.fade[i] <= 0.0f) ++finished;
        else ++still;
    };
    size_t k = 0;
#if defined(__SSE2__)
    // Four steps tested at once: most samples are settled (step 0), and a body of 75k samples
    // read them one by one every frame (8 % of the bunny's density pass).
    const __m128 zero = _mm_setzero_ps();
    for (; k + 4 <= n; k += 4) {
        uint32_t lanes = uint32_t(_mm_movemask_ps(_mm_cmpneq_ps(_mm_loadu_ps(s.fade_step.data() + k), zero)));
        for (; lanes != 0; lanes &= lanes - 1) advance(k + size_t(std::countr_zero(lanes)));
    }
#endif
    for (; k < n; ++k) advance(k);
    if (fading) *fading = still;
    // Faded out, a sample is invisible (zero opacity) and out of every test (retiring): it
    // leaves with the next batch, once a 64th of the samples has finished or nothing else
    // fades. Compacting every array of the bunny's 75k samples on each frame that some finished
    // was 15 % of its density pass.
    if (finished == 0 || (finished * 64 < n && still > 0)) return 0;
    return s.keep_if([&](size_t i) { return !(s.retiring(i) && s.fade[i] <= 0.0f); });
}

void fade_in(BoundaryParticles& s, size_t first, uint32_t frames) {
    s.pad_fades();
    const float step = 1.0f / float(std::max(1u, frames));
    for (size_t i = first; i < s.size(); ++i) {
        s.fade[i] = 0.0f;
        s.fade_step[i] = step;
    }
}

SpacingReport spacing_report(std::span<const Vec3f> points, float h, const SpacingQuery& query) {
    PBDSPLAT_ASSERT(query.normals.empty() || query.normals.size() == points.size(),
                    "spacing_report: give one normal per point, or none");
    SpacingReport r;
    r.points = std::min(query.measured, points.size());
    if (points.size() < 2 || r.points == 0) return r;
    // Cells of 2h: a nearest neighbour farther than that counts as "too far" anyway.
    PointGrid grid(2.0f * h, points.size());
    for (const Vec3f& p : points) grid.add(p);
    constexpr float same_side = 0.5f;  // cos 60 degrees
    std::vector<float> d(r.points);
    size_t in = 0;
    for (size_t i = 0; i < r.points; ++i) {
        const float d2 = query.normals.empty()
                             ? grid.nearest_squared(points[i], uint32_t(i))
                             : grid.nearest_squared_if(points[i], [&](uint32_t j) {
                                   return j != i && query.normals[j].dot(query.normals[i]) >= same_side;
                               });
        d[i] = std::isfinite(d2) ? std::sqrt(d2) / h : 2.0f;
        in += d[i] >= query.low && d[i] <= query.high;
    }
    r.within = float(in) / float(r.points);
    auto q = [&](float f) {
        const size_t k = std::min(d.size() - 1, size_t(f * float(d.size())));
        std::nth_element(d.begin(), d.begin() + k, d.end());
        return d[k];
    };
    r.p05 = q(0.05f);
    r.median = q(0.5f);
    r.p95 = q(0.95f);
    return r;
}

} // namespace pbdsplat::surface
