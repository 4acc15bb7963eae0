#include "sim/solver.h"

#include <cmath>
#include <type_traits>

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
StageTimings SolverT<Real>::step(SoftBodyT<Real>& body, float dt, const SolverSettings& s, const Colliders& colliders,
                                 const DragConstraint& drag) {
    StageTimings t;
    ParticlesT<Real>& p = body.particles;
    const Real h = Real(dt) / Real(s.substeps);
    const bool xpbd = s.mode == SolverMode::xpbd;
    const uint32_t projections = s.iterations * s.substeps;
    const Real k_stretch = Real(per_iteration(s.stretch_stiffness, projections));
    const Real k_volume = Real(per_iteration(s.volume_stiffness, projections));
    const bool volume = s.volume && !body.volumes.empty();
    if (volume && scratch_.size() != p.size()) scratch_.assign(p.size(), Vec4<Real>::Zero());

    for (uint32_t sub = 0; sub < s.substeps; ++sub) {
        core::Stopwatch clock;
        apply_external_forces(p, s.gravity, s.damping, h);
        predict_positions(p, h);
        t.apply_forces += clock.elapsed_ms();

        clock.restart();
        if (xpbd) {
            std::fill(body.distance_lambda.begin(), body.distance_lambda.end(), Real(0));
            for (VolumeConstraint& v : body.volumes) v.lambda = 0.0;
        }
        const Real inv_h2 = Real(1) / (h * h);
        for (uint32_t it = 0; it < s.iterations; ++it) {
            if (xpbd) project_distance_xpbd<Real>(body.distance, body.distance_lambda, p, inv_h2);
            else project_distance_pbd<Real>(body.distance, p, k_stretch);
            if (volume)
                for (VolumeConstraint& v : body.volumes)
                    solve_volume<Real>(v, p, scratch_, xpbd, k_volume, Real(v.compliance) * inv_h2);
            solve_drag(drag, p);
            solve_collisions(colliders, p);
        }
        t.constraints += clock.elapsed_ms();

        clock.restart();
        update_velocities(p, h);
        t.integrate_normals += clock.elapsed_ms();
    }
    if constexpr (std::is_same_v<Real, float>) {
        core::Stopwatch clock;
        update_normals(body.triangles, p.x, body.normals);
        t.integrate_normals += clock.elapsed_ms();
    }
    return t;
}

template class SolverT<float>;
template class SolverT<double>;

} // namespace pbdsplat::sim
