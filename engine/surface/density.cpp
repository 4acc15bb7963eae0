#include "surface/density.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "core/assert.h"
#include "mesh/deformation.h"
#include "surface/crowding.h"
#include "surface/embedding.h"
#include "surface/point_grid.h"

namespace pbdsplat::surface {
namespace {

// Index lists by key (compressed rows): keys [0, n), values in insertion order.
struct Rows {
    std::vector<uint32_t> start, items;
    std::span<const uint32_t> operator[](uint32_t k) const { return {items.data() + start[k], items.data() + start[k + 1]}; }
};
template <class KeyOf>
Rows make_rows(size_t keys, size_t count, const KeyOf& key_of) {
    Rows r;
    r.start.assign(keys + 1, 0);
    for (size_t i = 0; i < count; ++i) ++r.start[key_of(i) + 1];
    for (size_t k = 0; k < keys; ++k) r.start[k + 1] += r.start[k];
    r.items.resize(r.start.back());
    std::vector<uint32_t> fill(r.start.begin(), r.start.end() - 1);
    for (size_t i = 0; i < count; ++i) r.items[fill[key_of(i)]++] = uint32_t(i);
    return r;
}

// SplitMix64: a 64-bit counter through a mixing function; plenty for throwing darts.
struct SplitMix {
    uint64_t state;
    uint32_t next() {
        uint64_t z = (state += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return uint32_t((z ^ (z >> 31)) >> 32);
    }
    float unit() { return float(next() >> 8) * (1.0f / 16777216.0f); }  // [0, 1)
};

} // namespace

DensityControl::DensityControl(std::span<const Vec3f> rest, std::span<const mesh::Triangle> triangles, const DensityOptions& o)
    : options_(o) {
    inverse_rest_.resize(triangles.size());
    for (uint32_t t = 0; t < triangles.size(); ++t) set_rest(rest, triangles, t);
    stretch_.assign(triangles.size(), 1.0f);
    squeeze_.assign(triangles.size(), 1.0f);
    reference_.assign(triangles.size(), 1.0f);
    reference_squeeze_.assign(triangles.size(), 1.0f);
    beyond_.assign(triangles.size(), 0);
    checked_stretch_.assign(triangles.size(), 1.0f);
    checked_squeeze_.assign(triangles.size(), 1.0f);
    // A fresh maximal sampling has neither crowds nor gaps: the samples' trigger waits for a change.
    changed_.assign(triangles.size(), 0);
}

void DensityControl::set_rest(std::span<const Vec3f> rest, std::span<const mesh::Triangle> triangles, uint32_t t) {
    // A sliver (zero inverse) is never resampled: its neighbours cover it.
    inverse_rest_[t] = mesh::rest_frame_inverse(rest[triangles[t][0]], rest[triangles[t][1]], rest[triangles[t][2]]);
}

void DensityControl::topology_changed(std::span<const Vec3f> rest, std::span<const mesh::Triangle> triangles,
                                      std::span<const uint32_t> touched) {
    inverse_rest_.resize(triangles.size(), Eigen::Matrix2f::Zero());
    stretch_.resize(triangles.size(), 1.0f);
    squeeze_.resize(triangles.size(), 1.0f);
    reference_.resize(triangles.size(), 1.0f);
    reference_squeeze_.resize(triangles.size(), 1.0f);
    beyond_.resize(triangles.size(), 0);
    checked_stretch_.resize(triangles.size(), 1.0f);
    checked_squeeze_.resize(triangles.size(), 1.0f);
    changed_.resize(triangles.size(), 1);
    check_due_ = true;
    // A touched triangle was refilled from its rest shape: its samples stand for stretch 1.
    for (uint32_t t : touched) {
        set_rest(rest, triangles, t);
        reference_[t] = 1.0f;
        reference_squeeze_[t] = 1.0f;
        beyond_[t] = 0;
        changed_[t] = k_shrank | k_grew;
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
        bool anchors_drawn;
        float h;
        uint32_t seed;
        uint64_t frame;
        size_t max_samples;
    };
    Resampler(const Inputs& in, const DensityOptions& o, BoundaryParticles& s, DensityStats& stats)
        : in_(in), o_(o), s_(s), stats_(stats),
          by_triangle_(make_rows(in.triangles.size(), s.size(), [&](size_t i) { return s.triangle[i]; })),
          ring_(make_rows(in.x.size(), in.triangles.size() * 3, [&](size_t i) { return in.triangles[i / 3][i % 3]; })),
          mark_(in.triangles.size(), 0), step_(1.0f / float(std::max(1u, o.fade_frames))), embedded_(s.embedded()),
          fresh_(o.insert_spacing * in.h, 256) {
        s.pad_fades();
    }

    void insert(uint32_t t) {
        const auto& tri = in_.triangles[t];
        const Vec3f a = in_.x[tri[0]].head<3>(), b = in_.x[tri[1]].head<3>(), c = in_.x[tri[2]].head<3>();
        same_.assign(by_triangle_[t].begin(), by_triangle_[t].end());
        grid_.reset(o_.insert_spacing * in_.h);
        around(t, [&](uint32_t n) {
            for (uint32_t i : by_triangle_[n])
                if (!s_.retiring(i)) grid_.add(s_.position[i]);
            if (in_.anchors_drawn)
                for (uint32_t v : in_.triangles[n]) grid_.add(in_.x[v].head<3>());
        });
        // Samples inserted this frame (this triangle's and its neighbours', not in by_triangle
        // yet) are in fresh_, kept over the frame: copying them into every triangle's grid grew
        // with the frame's insertions.
        const Mat3f frame = triangle_frame(a, b, c);
        const float area = 0.5f * (b - a).cross(c - a).norm();
        const float expected = area * o_.candidates / (in_.h * in_.h);
        // A generator per triangle and frame, seeded in a few instructions: a Mersenne twister
        // seeded its 624 words for every resampled triangle (a fifth of balloon_inflate's run).
        SplitMix rng{(uint64_t(in_.seed) << 32) ^ (in_.frame * 0x9E3779B97F4A7C15ull) ^ (uint64_t(t) * 0xD1B54A32D192ED03ull)};
        uint32_t n = uint32_t(expected);
        if (rng.unit() < expected - float(n)) ++n;
        for (uint32_t k = 0; k < n; ++k) {
            float b1 = rng.unit(), b2 = rng.unit();
            if (b1 + b2 > 1.0f) b1 = 1.0f - b1, b2 = 1.0f - b2;
            const float b0 = 1.0f - b1 - b2;
            const Vec3f interpolated = b0 * in_.normals[tri[0]] + b1 * in_.normals[tri[1]] + b2 * in_.normals[tri[2]];
            float d = 0.0f;
            Vec3f local = Vec3f::UnitZ();
            if (embedded_) interpolate_embedding(s_, same_, Vec2f(b1, b2), d, local);
            const Vec3f p = b0 * a + b1 * b + b2 * c + d * interpolated;
            if (grid_.near(p) || fresh_.near(p)) continue;
            if (in_.max_samples && s_.size() >= in_.max_samples) {
                stats_.capped = true;
                break;
            }
            fresh_.add(p);
            s_.triangle.push_back(t);
            s_.bary.emplace_back(b1, b2);
            if (embedded_) s_.offset.push_back(d), s_.local_normal.push_back(local);
            s_.position.push_back(p);
            const float len = interpolated.norm();
            s_.normal.push_back(embedded_ ? Vec3f(surface_frame(a, b, c, interpolated) * local)
                                          : len > 0.0f ? Vec3f(interpolated / len) : frame.col(2));
            s_.fade.push_back(0.0f);
            s_.fade_step.push_back(step_);
            ++stats_.inserted;
        }
    }

    void retire(uint32_t t) {
        grid_.reset(o_.retire_spacing * in_.h);
        around(t, [&](uint32_t n) {
            if (n != t)
                for (uint32_t i : by_triangle_[n])
                    if (!s_.retiring(i)) grid_.add(s_.position[i]);
            if (in_.anchors_drawn)
                for (uint32_t v : in_.triangles[n]) grid_.add(in_.x[v].head<3>());
        });
        for (uint32_t i : by_triangle_[t]) {
            if (s_.retiring(i) || s_.on_edge(i)) continue;  // edge samples follow the boundary (surface/edges.h)
            if (grid_.near(s_.position[i])) {
                s_.fade_step[i] = -step_;
                ++stats_.retired;
            } else {
                grid_.add(s_.position[i]);
            }
        }
    }

private:
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

    Inputs in_;
    const DensityOptions& o_;
    BoundaryParticles& s_;
    DensityStats& stats_;
    Rows by_triangle_, ring_;
    std::vector<uint32_t> mark_;
    uint32_t stamp_ = 0;
    float step_;
    bool embedded_;
    std::vector<uint32_t> same_;
    PointGrid grid_{1.0f, 256};  // reset per triangle
    PointGrid fresh_;            // every sample inserted this frame
};

} // namespace

std::vector<DensityControl::Due> DensityControl::due_triangles(std::span<const Vec4f> x, std::span<const mesh::Triangle> triangles) {
    std::vector<Due> work;
    for (uint32_t t = 0; t < triangles.size(); ++t) {
        const auto& tri = triangles[t];
        const Vec3f e1 = (x[tri[1]] - x[tri[0]]).head<3>(), e2 = (x[tri[2]] - x[tri[0]]).head<3>();
        const mesh::Stretch sigma = inverse_rest_[t].isZero() ? mesh::Stretch{reference_[t], reference_squeeze_[t]}
                                                              : mesh::stretches(inverse_rest_[t], e1, e2);
        stretch_[t] = sigma.largest;
        squeeze_[t] = sigma.smallest;
        constexpr float k_changed = 0.05f;
        const float large = checked_stretch_[t], small = checked_squeeze_[t];
        const uint8_t was = changed_[t];
        if (sigma.largest < (1.0f - k_changed) * large || sigma.smallest < (1.0f - k_changed) * small) changed_[t] |= k_shrank;
        if (sigma.largest > (1.0f + k_changed) * large || sigma.smallest > (1.0f + k_changed) * small) changed_[t] |= k_grew;
        if (changed_[t] != was) check_due_ = true;
        const float ratio = sigma.largest / reference_[t];
        // Along its least stretched direction as well: a triangle squashed one way keeps its
        // largest stretch while its samples crowd along the other (a body landing), and when it
        // springs back the gaps open along that direction only.
        const float squeeze = sigma.smallest / std::max(reference_squeeze_[t], 1e-6f);
        const bool grow = ratio > options_.grow || squeeze > 1.0f / options_.squash;
        const bool thin = (ratio < options_.shrink || squeeze < options_.squash) && sigma.smallest > 0.0f;
        const int8_t side = grow ? 1 : thin ? -1 : 0;
        int8_t& run = beyond_[t];
        // Frames in a row on this side, counted up to 120 (the settle limit is at most 60).
        run = side == 0 ? 0 : run * side > 0 ? int8_t(side * std::min(std::abs(int(run)) + 1, 120)) : side;
        if (uint32_t(std::abs(run)) < std::max(1u, options_.settle_frames)) continue;
        const float priority = std::max(std::abs(std::log(ratio)), std::abs(std::log(std::max(squeeze, 1e-6f))));
        work.push_back({priority, t, grow, thin});
    }
    return work;
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
        if (!resampler) resampler.emplace(Resampler::Inputs{x, normals, triangles, anchors_drawn, h, seed, frame_, max_samples_}, options_, s, stats);
        return *resampler;
    };
    auto sampled = [&](uint32_t t) {
        reference_[t] = stretch_[t];
        reference_squeeze_[t] = squeeze_[t];
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
    if (by_samples && check_due_ && frame_ >= checked_frame_ + std::max(1u, options_.settle_frames)) {
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
        CrowdingResult c = thin_crowds(x, normals, triangles, q, s);
        stats.crowded = c.retired;
        stats.retired += c.retired;
        // Refill wherever no sample reaches, within what the triangles' work left of the budget.
        // Not the crowded samples' own triangles: on a surface still folding, samples thrown
        // there crowd again a few frames later (the teapot deflating: 80-100 retired every 4
        // frames for 200 frames, against 1,300 in all without).
        const size_t room = options_.budget - std::min<size_t>(options_.budget, stats.resampled);
        for (size_t k = 0; k < c.gaps.size() && k < room; ++k) {
            if (inverse_rest_[c.gaps[k]].isZero()) continue;
            r().insert(c.gaps[k]);
            sampled(c.gaps[k]);
            ++stats.gaps;
            ++stats.resampled;
        }
        for (size_t t = 0; t < changed_.size(); ++t)
            if (changed_[t]) changed_[t] = 0, checked_stretch_[t] = stretch_[t], checked_squeeze_[t] = squeeze_[t];
        checked_frame_ = frame_;
        check_due_ = false;
    }
    stats.removed = uint32_t(advance_fades(s, &stats.fading));
    return stats;
}

size_t advance_fades(BoundaryParticles& s, uint32_t* fading) {
    uint32_t still = 0;
    bool remove = false;
    const size_t n = std::min(s.fade.size(), s.fade_step.size());
    for (size_t i = 0; i < n; ++i) {
        if (s.fade_step[i] == 0.0f) continue;
        s.fade[i] = std::clamp(s.fade[i] + s.fade_step[i], 0.0f, 1.0f);
        if (s.fade_step[i] > 0.0f && s.fade[i] >= 1.0f) s.fade_step[i] = 0.0f;
        else if (s.fade_step[i] < 0.0f && s.fade[i] <= 0.0f) remove = true;
        else ++still;
    }
    if (fading) *fading = still;
    if (!remove) return 0;
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
