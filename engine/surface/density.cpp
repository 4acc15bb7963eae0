#include "surface/density.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "core/assert.h"
#include "mesh/deformation.h"
#include "surface/crowding.h"
#include "surface/resampler.h"
#include "surface/rows.h"
#include "surface/stretch_scan.h"

namespace pbdsplat::surface {
namespace {

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
        publish_growth(s);
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
    publish_growth(s);
    return stats;
}

void DensityControl::publish_growth(BoundaryParticles& s) const {
    // A maximal set at spacing h leaves no point farther than about h from a sample, and the
    // splats' Gaussians close that much with room to spare: stretched by the refill threshold
    // `grow` (1.1) the set still covers 0.98 midway between three samples. Stretched further (a
    // sudden inflation waiting out the settle frames and the budget) the background shows dimly
    // between them: a sphere inflated by 1.35 at once, seen close, left 1.9 % of its pixels
    // covered under 0.9. Its splats grow by the stretch past `grow`, so they close what the
    // stretched set spans; within the threshold they keep their size (grown there too, the
    // default scene's splat pass took 7-14 % longer on Lavapipe for nothing a user sees). At
    // most k_max_growth: beyond, a late refill costs less than the blur. With the control off
    // the samples stay as they are, as asked (`surface.stretch_scale` grows the splats instead).
    constexpr float k_max_growth = 2.0f;
    if (!options_.enabled) {
        s.triangle_growth.clear();
        return;
    }
    const float allowed2 = options_.grow * options_.grow;
    s.triangle_growth.resize(stretch2_.size());
    for (size_t t = 0; t < stretch2_.size(); ++t) {
        const float ratio = reference2_[t] > 0.0f ? stretch2_[t] / (reference2_[t] * allowed2) : 1.0f;
        s.triangle_growth[t] = ratio > 1.0f ? std::min(std::sqrt(ratio), k_max_growth) : 1.0f;
    }
}

} // namespace pbdsplat::surface
