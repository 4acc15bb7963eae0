#pragma once
// Boundary particles kept at the sampling density while the surface deforms (paper sections
// 4.2 and 5.2: samples "updated every frame to preserve the sampling density"). Samples ride
// on the simulation triangles; where a triangle has stretched by `grow` since it was last
// sampled, new samples are thrown onto its deformed shape (the maximal sampler, run locally,
// h away from every sample near it); where it has shrunk to `shrink`, samples closer than
// `retire_spacing` h to a kept one retire. New samples fade in, retired ones fade out and
// then leave. Between the two thresholds nothing happens (hysteresis: no flicker), and a
// per-frame budget of triangles spreads a sudden inflation over several frames.
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "core/math.h"
#include "mesh/triangle_mesh.h"
#include "surface/boundary_particles.h"
#include "surface/fades.h"
#include "surface/rows.h"

namespace pbdsplat::surface {

struct DensityOptions {
    bool enabled = true;
    float grow = 1.1f;            // resample a triangle stretched this much since its last sampling
    float shrink = 0.9f;          // thin a triangle shrunk to this
    // Thin a triangle squashed to this along its least stretched direction (its largest stretch
    // unchanged: a body landing), and grow it again when it springs back past 1 / squash. Wider
    // than shrink: a tumbling body's triangles jiggle by 10 % along that direction, and at 0.9
    // the bunny's pieces churned 48k samples in and 42k out over 300 frames (28k / 25k without
    // the test; 39k / 35k at 0.8, 35k / 31k at 0.7).
    float squash = 0.75f;
    float retire_spacing = 0.9f;  // thinning keeps samples at least this many h apart
    // New samples keep this many h from every other. Below 1: a maximal set at spacing h
    // leaves neighbours up to 2h apart, and a stretched one more; only a closer throw splits them.
    float insert_spacing = 0.85f;
    uint32_t budget = 512;        // triangles resampled per frame, largest change first
    uint32_t fade_frames = 6;     // new samples fade in, retired ones out, over this many frames
    // A triangle must stay past a threshold this many frames in a row before it is resampled:
    // a landing or a jiggle that squashes it for a moment changes nothing (no churn, no flicker).
    uint32_t settle_frames = 4;
    // Candidate points per h^2 of deformed area. A resampled triangle already carries samples,
    // so most darts land near one: 48 (the initial sampler's) threw three times the darts for
    // the same result (balloon_inflate: spacing 0.991 -> 0.987, no hole, the pass's mean 1.18 ->
    // 0.71 ms); a gap a sparse throw misses is the samples' trigger's (gap_spacing).
    float candidates = 12.0f;
    // The trigger on the samples themselves (surface/crowding.h), run every settle_frames frames
    // while some triangle has shrunk or grown by more than 5 % since the last run: a sample on a
    // shrunk triangle nearer than crowd_spacing h to a kept one on its own side retires (0:
    // never), and a grown triangle whose centre lies farther than gap_spacing h from every
    // sample is resampled (0: never).
    float crowd_spacing = 0.7f;
    // Above the growth trigger's reach: a maximal set at spacing h stretched by `grow` leaves
    // centres up to about 1.1 h from a sample, and those are the triangles' business.
    float gap_spacing = 1.25f;
};

struct DensityStats {
    uint32_t resampled = 0;  // triangles grown or thinned this frame (gaps included)
    uint32_t pending = 0;    // triangles past a threshold left for later frames (budget)
    uint32_t inserted = 0, retired = 0, removed = 0;
    uint32_t fading = 0;     // samples still fading in or out
    uint32_t crowded = 0;    // samples retired by the samples' own trigger (in `retired` too)
    uint32_t gaps = 0;       // triangles resampled because no sample covered their centre (in `resampled` too)
    bool capped = false;     // insertion stopped at the sample limit (set_max_samples)
    bool checked = false;    // the samples' own trigger ran this frame
};

class DensityControl {
public:
    DensityControl() = default;
    // `rest` and `triangles`: the simulation mesh whose triangles carry the samples.
    DensityControl(std::span<const Vec3f> rest, std::span<const mesh::Triangle> triangles, const DensityOptions& options);
    bool empty() const { return inverse_rest_.empty(); }
    // No insertion past this many samples (the renderer's capacity); 0: no limit.
    void set_max_samples(size_t n) { max_samples_ = n; }

    // After a topology change: the listed triangles (new or re-shaped, new indices) were
    // refilled at rest spacing, the others kept their index and their samples.
    void topology_changed(std::span<const Vec3f> rest, std::span<const mesh::Triangle> triangles,
                          std::span<const uint32_t> touched);

    // One frame: measures every triangle's stretch, grows and thins within the budget, and
    // advances the fades (removing samples that finished fading out). `x`: the particles
    // (float4, w ignored); `normals`: their unit normals; `anchors_drawn`: the particles are
    // splats too, so they block new samples like samples do. Positions of the samples must be
    // current (update_boundary_particles) and are kept current for the new ones.
    DensityStats update(std::span<const Vec4f> x, std::span<const Vec3f> normals, std::span<const mesh::Triangle> triangles,
                        bool anchors_drawn, float h, uint32_t seed, BoundaryParticles& samples);

private:
    void set_rest(std::span<const Vec3f> rest, std::span<const mesh::Triangle> triangles, uint32_t t);
    // A triangle past a threshold long enough to be resampled this frame, most stretched first.
    struct Due {
        float priority;
        uint32_t triangle;
        bool grow;  // stretched: new samples
        bool thin;  // shrunk along some direction: retire the crowded (before any growing)
    };
    // The triangles around each particle (surface/rows.h), rebuilt after a topology change.
    const Rows& ring(size_t particles, std::span<const mesh::Triangle> triangles);
    std::vector<Due> due_triangles(std::span<const Vec4f> x, std::span<const mesh::Triangle> triangles);
    // The squared thresholds due_triangles judges by (squared stretches throughout: one square
    // root a triangle instead of three, no division).
    struct Thresholds {
        float grow2, shrink2, squash2, unsquash2;
        uint32_t settle;
    };
    // Triangle t's stretches (this frame's, in stretch2_ and squeeze2_) against its reference: its
    // change bits, its run of frames past a threshold, and a Due in `work` once the run settles.
    void judge(uint32_t t, const Thresholds& th, std::vector<Due>& work);
    // Each triangle's stretch past `grow` since it was last sampled into s.triangle_growth.
    void publish_growth(BoundaryParticles& s) const;
    // The samples' own trigger: crowded samples thinned, and the triangles no sample reaches
    // handed to `refill`, within `room` of them.
    void check_crowds(std::span<const Vec4f> x, std::span<const Vec3f> normals, std::span<const mesh::Triangle> triangles, bool anchors_drawn,
                      float h, BoundaryParticles& s, size_t room, DensityStats& stats, const std::function<void(uint32_t)>& refill);
    void arm_change_bounds(uint32_t t);     // from this frame's stretches, nothing recorded
    void disarm_change_bounds(uint32_t t);  // for the bits set in changed_[t]
    DensityOptions options_;
    std::vector<Eigen::Matrix2f> inverse_rest_;  // per triangle, in its own rest frame; zero for slivers
    // The same, laid out for the stretch scan's four lanes: per block of four triangles, their
    // a entries, then c, b, d (column-major order), so a block loads without a transpose.
    std::vector<float> inverse_rest_lanes_;
    // Per triangle, squared (the eigenvalues of F^T F): the largest and smallest stretch this
    // frame, and when the triangle was last sampled.
    std::vector<float> stretch2_, squeeze2_;
    std::vector<float> reference2_, reference_squeeze2_;
    std::vector<int8_t> beyond_;  // frames in a row past a threshold: + grow side, - shrink side
    std::vector<uint8_t> changed_;  // per triangle: k_shrank / k_grew since the samples' trigger last ran
    // Per triangle, the squared stretches (largest, smallest) below which it has shrunk and above
    // which it has grown by 5 % since the samples' trigger last ran; a bound is moved out of
    // reach once its change is recorded in changed_, so a triangle that has changed stops
    // drawing the scan's attention until the next run (with the wait between runs doubling, it
    // did so on every frame of the wait).
    std::vector<float> shrank_large2_, shrank_small2_, grew_large2_, grew_small2_;
    std::vector<uint32_t> busy_;  // this frame's triangles for the per-triangle logic (the scan's)
    Rows ring_;
    uint64_t checked_frame_ = 0;
    bool check_due_ = false;  // some triangle changed shape since (or the topology did)
    uint32_t check_wait_ = 0;  // frames from one check to the next (at least the settle frames)
    static constexpr uint32_t k_check_backoff = 4;
    uint64_t frame_ = 0;
    size_t max_samples_ = 0;
};

} // namespace pbdsplat::surface
