#include "sim/solver.h"

#include <cmath>
#include <type_traits>

#include "core/assert.h"
#include "core/timer.h"
#include "sim/collision.h"
#include "sim/distance.h"
#include "sim/drag.h"
#include "sim/integrate.h"
#include "sim/volume.h"

namespace pbdsplat::sim {

core::Status validate(const SolverSettings& s) {
    if (s.iterations < 1 || s.iterations > 1000) return core::make_error("iterations must be 1 to 1000");
    if (s.substeps < 1 || s.substeps > 1000) return core::make_error("substeps must be 1 to 1000");
    if (!s.gravity.allFinite()) return core::make_error("gravity must be finite");
    if (!(s.damping >= 0.0f) || !std::isfinite(s.damping)) return core::make_error("damping must be >= 0");
    if (!(s.stretch_stiffness > 0.0f && s.stretch_stiffness <= 1.0f))
        return core::make_error("stretch stiffness must be in (0, 1]");
    if (!(s.volume_stiffness > 0.0f && s.volume_stiffness <= 1.0f))
        return core::make_error("volume stiffness must be in (0, 1]");
    return core::Status::success();
}

namespace {
// PBD stiffness per projection, so that `iterations` projections close the same share of the
// error as one projection of stiffness k would "per frame" (Mueller et al. 2007, section 3.3).
float per_iteration(float k, uint32_t projections) {
    if (k >= 1.0f) return 1.0f;
    return 1.0f - std::pow(1.0f - k, 1.0f / float(projections));
}
} // namespace

template <class Real>
template <class Fn>
void SolverT<Real>::for_range(size_t n, size_t grain, const Fn& fn) {
    if (!pool_ || pool_->size() == 1 || n < grain) {
        fn(size_t(0), n);
        return;
    }
    pool_->parallel_for(n, [&](unsigned, size_t begin, size_t end) { fn(begin, end); });
}

template <class Real>
StageTimings SolverT<Real>::step(SoftBodyT<Real>& body, float dt, const SolverSettings& s, const Colliders& colliders,
                                 const DragConstraint& drag) {
    constexpr size_t k_particle_grain = 4096;  // below this a loop is cheaper than a hand-off
    StageTimings t;
    ParticlesT<Real>& p = body.particles;
    const size_t n = p.size();
    PBDSPLAT_ASSERT(body.distance_colours.empty() ? body.distance.empty() : body.distance_colours.back() == body.distance.size(),
                    "distance constraints changed without rebuild_derived(body)");
    PBDSPLAT_ASSERT(body.rings.start.size() == n + 1 && body.distance_lambda.size() == body.distance.size(),
                    "particles or triangles changed without rebuild_derived(body)");
    const Real h = Real(dt) / Real(s.substeps);
    const bool xpbd = s.mode == SolverMode::xpbd;
    const uint32_t projections = s.iterations * s.substeps;
    const Real k_stretch = Real(per_iteration(s.stretch_stiffness, projections));
    const Real k_volume = Real(per_iteration(s.volume_stiffness, projections));
    const bool volume = s.volume && !body.volumes.empty();
    if (volume && scratch_.size() != n) scratch_.assign(n, Vec4<Real>::Zero());
    const std::span<const DistanceConstraint> distance(body.distance);
    const std::span<Real> lambda(body.distance_lambda);

    for (uint32_t sub = 0; sub < s.substeps; ++sub) {
        core::Stopwatch clock;
        for_range(n, k_particle_grain, [&](size_t b, size_t e) { apply_forces_and_predict<Real>(p, s.gravity, s.damping, h, b, e); });
        t.apply_forces += clock.elapsed_ms();

        clock.restart();
        if (xpbd) {
            std::fill(lambda.begin(), lambda.end(), Real(0));
            for (VolumeConstraint& v : body.volumes) v.lambda = 0.0;
        }
        const Real inv_h2 = Real(1) / (h * h);
        for (uint32_t it = 0; it < s.iterations; ++it) {
            // Distance constraints colour by colour: inside a colour no two share a particle.
            for (size_t c = 0; c + 1 < body.distance_colours.size(); ++c) {
                const size_t first = body.distance_colours[c], count = body.distance_colours[c + 1] - first;
                for_range(count, 2048, [&](size_t b, size_t e) {
                    if (xpbd) project_distance_xpbd<Real>(distance.subspan(first + b, e - b), lambda.subspan(first + b, e - b), p, inv_h2);
                    else project_distance_pbd<Real>(distance.subspan(first + b, e - b), p, k_stretch);
                });
            }
            if (volume)
                for (VolumeConstraint& v : body.volumes) {
                    const size_t blocks = volume_blocks(v);
                    sums_.assign(blocks, VolumeSums{});
                    for_range(blocks, 2, [&](size_t b, size_t e) {
                        for (size_t k = b; k < e; ++k) sums_[k] = volume_gather<Real>(v, p, scratch_, k);
                    });
                    volume_caps<Real>(v, p, scratch_, sums_);
                    const Real step = volume_step<Real>(v, sums_, xpbd, k_volume, Real(v.compliance) * inv_h2);
                    for_range(blocks, 2, [&](size_t b, size_t e) {
                        for (size_t k = b; k < e; ++k) volume_apply<Real>(v, p, scratch_, step, k);
                    });
                }
            solve_drag(drag, p);
            if (!colliders.empty())
                for_range(n, k_particle_grain, [&](size_t b, size_t e) { solve_collisions<Real>(colliders, p, b, e); });
        }
        t.constraints += clock.elapsed_ms();

        clock.restart();
        for_range(n, k_particle_grain, [&](size_t b, size_t e) { update_velocities<Real>(p, h, b, e); });
        t.integrate_normals += clock.elapsed_ms();
    }
    if constexpr (std::is_same_v<Real, float>) {
        core::Stopwatch clock;
        body.normals.resize(n);
        for_range(n, k_particle_grain, [&](size_t b, size_t e) { update_normals(body.rings, p.x, body.normals, b, e); });
        t.integrate_normals += clock.elapsed_ms();
    }
    return t;
}

template class SolverT<float>;
template class SolverT<double>;

} // namespace pbdsplat::sim
