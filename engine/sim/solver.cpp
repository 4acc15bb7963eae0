#include "sim/solver.h"

#include <cmath>
#include <type_traits>

#include "core/assert.h"
#include "core/timer.h"
#include "sim/approach.h"
#include "sim/collision.h"
#include "sim/distance.h"
#include "sim/drag.h"
#include "sim/integrate.h"
#include "sim/shape.h"
#include "sim/weld.h"
#include "sim/volume.h"

namespace pbdsplat::sim {

core::Status validate(const SolverSettings& s) {
    if (s.iterations < 1 || s.iterations > 1000) return core::make_error("iterations must be 1 to 1000");
    if (s.substeps < 1 || s.substeps > 1000) return core::make_error("substeps must be 1 to 1000");
    if (s.contact.substeps < 1 || s.contact.substeps > 1000) return core::make_error("contact substeps must be 1 to 1000");
    if (!s.gravity.allFinite()) return core::make_error("gravity must be finite");
    if (!(s.damping >= 0.0f) || !std::isfinite(s.damping)) return core::make_error("damping must be >= 0");
    if (!(s.deform_damping >= 0.0f) || !std::isfinite(s.deform_damping)) return core::make_error("deform_damping must be >= 0");
    if (!(s.stretch_stiffness > 0.0f && s.stretch_stiffness <= 1.0f))
        return core::make_error("stretch stiffness must be in (0, 1]");
    if (!(s.volume_stiffness > 0.0f && s.volume_stiffness <= 1.0f))
        return core::make_error("volume stiffness must be in (0, 1]");
    if (!(s.shape_stiffness >= 0.0f && s.shape_stiffness <= 1.0f))
        return core::make_error("shape stiffness must be in [0, 1] (0 turns shape matching off)");
    if (!(s.shape_compliance >= 0.0f) || !std::isfinite(s.shape_compliance))
        return core::make_error("shape compliance must be >= 0");
    if (!(s.contact.thickness >= 0.0f) || !std::isfinite(s.contact.thickness))
        return core::make_error("contact thickness must be >= 0 (0: a quarter of the mean edge length)");
    if (!(s.contact.friction.kinetic >= 0.0f && s.contact.friction.static_ >= 0.0f) || !std::isfinite(s.contact.friction.kinetic) ||
        !std::isfinite(s.contact.friction.static_))
        return core::make_error("friction coefficients must be finite and >= 0");
    return core::Status::success();
}

float raised_scale(const SolverSettings& s, float shape_stiffness, float exponent, float fade) {
    if (s.mode == SolverMode::xpbd || !(shape_stiffness < k_rigid_response_stiffness) || s.tuned_substeps == 0 ||
        s.substeps <= s.tuned_substeps || !(fade > 0.0f))
        return 1.0f;
    return std::pow(float(s.tuned_substeps) / float(s.substeps), exponent * fade);
}

namespace {
constexpr float k_raise_faded = 1e-3f;
} // namespace

template <class Real>
void SolverT<Real>::fade_raise(const SolverSettings& s, Real h) {
    if (s.tuned_substeps == 0 || s.substeps <= s.tuned_substeps) {
        raise_fade_ = 0.0f, raise_substeps_ = 0;
        return;
    }
    // A rise (from the scene's substeps or a lesser raise) softens afresh; a fall within the
    // raise keeps fading.
    if (s.substeps > raise_substeps_) raise_fade_ = 1.0f;
    else raise_fade_ *= std::exp(-float(h) / k_raise_firming);
    // Seven time constants on, the scale is within 0.5 % of 1 (at a raise of 16): done, and the
    // edges go back to one stiffness for the whole body instead of one per constraint.
    if (raise_fade_ < k_raise_faded) raise_fade_ = 0.0f;
    raise_substeps_ = s.substeps;
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

namespace {
constexpr size_t k_particle_grain = 4096;  // below this a loop is cheaper than a hand-off
}

template <class Real>
void SolverT<Real>::stretch_per_constraint(const SoftBodyT<Real>& body, const SolverSettings& s) {
    // Once a substep: a cut between frames re-points and adds constraints, and the frame's
    // substeps (so each projection's share) may change.
    const std::vector<float>& own = body.model_stretch_stiffness;
    const std::vector<float>& shape = body.model_shape_stiffness;
    const bool raised = raise_fade_ > 0.0f;
    const bool per_model = !own.empty() || (raised && !shape.empty());
    if (!per_model || s.mode == SolverMode::xpbd || body.model_of_particle.size() != body.particles.size()) {
        distance_k_.clear();
        return;
    }
    // One entry past the longer list: the models it does not name take the settings'.
    std::vector<Real> k_of(std::max(own.size(), shape.size()) + 1);
    for (size_t m = 0; m < k_of.size(); ++m) {
        const float k = m < own.size() && own[m] > 0.0f ? own[m] : s.stretch_stiffness;
        const float k_shape = m < shape.size() && shape[m] >= 0.0f ? shape[m] : s.shape_stiffness;
        k_of[m] = Real(raised_scale(s, k_shape, k_raised_edges, raise_fade_) * per_iteration(k, s.iterations * s.substeps));
    }
    distance_k_.resize(body.distance.size());
    for (size_t c = 0; c < body.distance.size(); ++c)
        distance_k_[c] = k_of[std::min<size_t>(body.model_of_particle[body.distance[c].i], k_of.size() - 1)];
}

template <class Real>
void SolverT<Real>::begin_substep(SoftBodyT<Real>& body, const SolverSettings& s, Real h) {
    ParticlesT<Real>& p = body.particles;
    PBDSPLAT_ASSERT(body.distance_groups.start.empty() ? body.distance.empty() : body.distance_groups.start.back() == body.distance.size(),
                    "distance constraints changed without rebuild_derived(body)");
    PBDSPLAT_ASSERT(body.rings.size() == p.size() && body.distance_lambda.size() == body.distance.size(),
                    "particles or triangles changed without rebuild_derived(body)");
    if (body.model_damping.empty() || body.model_of_particle.size() != p.size()) {
        for_range(p.size(), k_particle_grain, [&](size_t b, size_t e) { apply_forces_and_predict<Real>(p, s.gravity, s.damping, h, b, e); });
    } else {
        // Each model's own rate, or the settings'; a model past the list (none is) the settings'.
        const std::vector<float>& rate = body.model_damping;
        model_keep_.assign(body.model_count(), Real(1));
        for (size_t m = 0; m < model_keep_.size(); ++m) {
            const float r = m < rate.size() && rate[m] >= 0.0f ? rate[m] : s.damping;
            model_keep_[m] = r > 0.0f ? std::exp(-Real(r) * h) : Real(1);
        }
        for_range(p.size(), k_particle_grain,
                  [&](size_t b, size_t e) { apply_forces_and_predict<Real>(p, s.gravity, model_keep_, body.model_of_particle, h, b, e); });
    }
    fade_raise(s, h);
    stretch_per_constraint(body, s);
    if (!body.volumes.empty()) slots_.weights = volume_weights<Real>(std::span<const Real>(p.w), body.rings.rest_area);
    slots_.pressed.clear();  // find_contacts fills it where contact runs
    slots_.moments_ready.clear();
    for (VolumeConstraint& v : body.volumes)
        if (v.leak > 0.0f)
            v.pressure = VolumeConstraint::k_emptied + (v.pressure - VolumeConstraint::k_emptied) * std::exp(-leak_rate(v, p.x) * float(h));
    if (s.mode == SolverMode::xpbd) {
        std::fill(body.distance_lambda.begin(), body.distance_lambda.end(), Real(0));
        for (VolumeConstraint& v : body.volumes) v.lambda = 0.0;
    }
}

template <class Real>
void SolverT<Real>::project_distance(const BodyStructureT<Real>& structure, BodyStateT<Real>& state, const SolverSettings& s, Real h) {
    ParticlesT<Real>& p = state.particles;
    const std::span<const DistanceConstraint> distance(structure.distance);
    const std::span<Real> lambda(state.distance_lambda);
    const bool xpbd = s.mode == SolverMode::xpbd;
    // Welds glue parts, whatever they are made of: never softened (raised_scale).
    const Real k_welds = Real(per_iteration(s.stretch_stiffness, s.iterations * s.substeps));
    const Real k = k_welds * Real(raised_scale(s, s.shape_stiffness, k_raised_edges, raise_fade_));
    const Real inv_h2 = Real(1) / (h * h);
    const bool each = !xpbd && distance_k_.size() == distance.size();  // models of their own stiffness
    const std::span<const Real> each_k(distance_k_);
    // Colour by colour: inside a colour no two constraints share a particle.
    for (size_t c = 0; c + 1 < structure.distance_groups.start.size(); ++c) {
        const size_t first = structure.distance_groups.start[c], count = structure.distance_groups.start[c + 1] - first;
        for_range(count, 2048, [&](size_t b, size_t e) {
            if (xpbd) project_distance_xpbd<Real>(distance.subspan(first + b, e - b), lambda.subspan(first + b, e - b), p, inv_h2);
            else if (each) project_distance_pbd<Real>(distance.subspan(first + b, e - b), each_k.subspan(first + b, e - b), p);
            else project_distance_pbd<Real>(distance.subspan(first + b, e - b), p, k);
        });
    }
    project_welds<Real>(structure, p, k_welds);
}

template <class Real>
void SolverT<Real>::project_volume(SoftBodyT<Real>& body, const SolverSettings& s, Real h) {
    ParticlesT<Real>& p = body.particles;
    if (scratch_.size() != p.size()) scratch_.assign(p.size(), Vec4<Real>::Zero());
    const bool xpbd = s.mode == SolverMode::xpbd;
    const Real k = Real(per_iteration(s.volume_stiffness, s.iterations * s.substeps));
    const Real inv_h2 = Real(1) / (h * h);
    const VolumeLayout l = volume_layout(body, slots_);
    const size_t slots = l.slots, blocks = volume_blocks(p.size());
    if (slots == 0) return;
    sums_.resize(blocks);
    for_range(blocks, 2, [&](size_t b, size_t e) {
        for (size_t q = b; q < e; ++q) volume_gather<Real>(l, p, scratch_, q, sums_[q]);
    });
    totals_.resize(slots);
    reduce_blocks<VolumeSums>(sums_, totals_);
    steps_.resize(slots), nudges_.resize(slots);
    for (size_t slot = 0; slot < slots; ++slot) {
        VolumeConstraint& v = *slots_.constraints[slot];
        VolumeSums& total = totals_[slot];
        VolumeSums caps;
        v.measured_six_v = total.eighteen_v / 3.0;  // before the caps: 3 x (6V of the triangles)
        volume_caps<Real>(l, v, p, scratch_, caps);
        v.measured_caps_six_v = caps.eighteen_v / 3.0;  // the caps' own 6V (their correction is 3 x that)
        total.add(caps);
        steps_[slot] = volume_step<Real>(v, total, xpbd, k, Real(v.compliance) * inv_h2);
    }
    rigid_nudges(body, l);
    for_range(blocks, 2, [&](size_t b, size_t e) {
        for (size_t q = b; q < e; ++q) volume_apply<Real>(l, p, scratch_, steps_, nudges_, q);
    });
}

template <class Real>
void SolverT<Real>::rigid_nudges(const SoftBodyT<Real>& body, const VolumeLayout& l) {
    const size_t slots = l.slots, blocks = volume_blocks(body.particles.size());
    slots_.moments.resize(slots), slots_.moments_ready.resize(slots, 0), wanted_.assign(slots, 0);
    // A pressed piece's impulse is the contact's to answer: no nudge for it.
    const auto pressed = [&](size_t slot) {
        const uint32_t piece = slots_.constraints[slot]->piece;
        return piece < slots_.pressed.size() && slots_.pressed[piece] != 0;
    };
    bool any = false;
    for (size_t slot = 0; slot < slots; ++slot) {
        nudges_[slot] = RigidNudge<Real>{};
        if (!pressed(slot) && totals_[slot].unbalanced() && !slots_.moments_ready[slot]) wanted_[slot] = 1, any = true;
    }
    if (any) {
        moment_blocks_.resize(blocks), moments_.resize(slots);
        for_range(blocks, 2, [&](size_t b, size_t e) {
            for (size_t q = b; q < e; ++q) volume_moments<Real>(l, body.particles, wanted_, q, moment_blocks_[q]);
        });
        reduce_blocks<MassMoments>(moment_blocks_, moments_);
        for (size_t slot = 0; slot < slots; ++slot)
            if (wanted_[slot]) slots_.moments[slot] = moments_[slot], slots_.moments_ready[slot] = 1;
    }
    for (size_t slot = 0; slot < slots; ++slot)
        if (!pressed(slot) && slots_.moments_ready[slot]) nudges_[slot] = volume_nudge<Real>(totals_[slot], slots_.moments[slot], steps_[slot]);
}

template <class Real>
void SolverT<Real>::project_shape(BodyCachesT<Real>& caches, BodyStateT<Real>& state, const SolverSettings& s, Real h) {
    if (caches.shapes.empty()) return;
    const bool xpbd = s.mode == SolverMode::xpbd && s.shape_compliance > 0.0f;
    const Real alpha = Real(s.shape_compliance) / (h * h);
    const uint32_t sweeps = s.iterations * s.substeps;
    // Pieces are independent: one per thread when there are several large ones. Each keeps its
    // body's stiffness (a soft body beside a stiff one); one of none is left to its constraints.
    for_range(caches.shapes.size(), 2, [&](size_t b, size_t e) {
        for (size_t c = b; c < e; ++c) {
            const float stiffness = stiffness_of(caches.shapes[c], s.shape_stiffness);
            if (!(stiffness > 0.0f)) continue;
            const float raised = raised_scale(s, stiffness, k_raised_shape, raise_fade_);
            sim::project_shape<Real>(caches.shapes[c], state.particles, Real(raised * per_iteration(stiffness, sweeps)), xpbd, alpha);
        }
    });
}

template <class Real>
void SolverT<Real>::apply_drag(BodyStateT<Real>& state, const DragConstraint& drag) {
    solve_drag(drag, state.particles);
}

template <class Real>
void SolverT<Real>::collide(BodyStateT<Real>& state, const Colliders& colliders) {
    if (colliders.empty()) return;
    for_range(state.particles.size(), k_particle_grain,
              [&](size_t b, size_t e) { solve_collisions<Real>(colliders, state.particles, b, e); });
}

template <class Real>
void SolverT<Real>::find_contacts(SoftBodyT<Real>& body, const SolverSettings& s) {
    const float g = s.gravity.norm();
    contact_.set_up(g > 0.0f ? Vec3f(-s.gravity / g) : Vec3f::Zero());
    contact_.find(body, s.contact, s.shape_stiffness);
    stiff_contact_ = stiffest_shape(body.shapes, s.shape_stiffness) >= k_rigid_response_stiffness;
    // A soft body beside stiff ones is guarded with them (a stiff surface is never pushed: it does
    // not fold); stiff bodies alone pay nothing.
    folds_.find(body, s.contact, softest_shape(body.shapes, s.shape_stiffness) >= k_rigid_response_stiffness);
    // The pieces that meet another: the volume pass leaves their net impulse where it falls.
    pressed_pairs_.clear();
    contact_.touching_pieces(body, pressed_pairs_);
    slots_.pressed.assign(body.pieces, 0);
    for (const auto& [a, b] : pressed_pairs_) slots_.pressed[a] = slots_.pressed[b] = 1;
}

template <class Real>
void SolverT<Real>::project_contacts(SoftBodyT<Real>& body, const SolverSettings& s) {
    contact_.project(body, s.contact, stiff_contact_);
    folds_.project(body.particles);
    if (!contact_.pressed_sleepers().empty()) {
        wake_pieces<Real>(body, contact_.pressed_sleepers());
        contact_.clear_pressed_sleepers();
    }
}

template <class Real>
void SolverT<Real>::end_substep(SoftBodyT<Real>& body, const SolverSettings& s, Real h) {
    for_range(body.particles.size(), k_particle_grain, [&](size_t b, size_t e) { update_velocities<Real>(body.particles, h, b, e); });
    const std::vector<float>& own = body.model_deform_damping;
    const bool models_known = body.model_of_particle.size() == body.particles.size();
    if (!(s.deform_damping > 0.0f) && (own.empty() || !models_known)) return;
    // Each piece the rate of its model (a piece never spans two).
    piece_rate_.assign(body.pieces, -1.0f);
    for (size_t i = 0; i < body.particles.size(); ++i) {
        const uint32_t k = body.piece_of_particle[i];
        if (k >= piece_rate_.size() || piece_rate_[k] >= 0.0f) continue;
        const uint32_t m = models_known ? body.model_of_particle[i] : 0u;
        piece_rate_[k] = m < own.size() && own[m] >= 0.0f ? own[m] : s.deform_damping;
    }
    damp_deformation<Real>(body.particles, body.piece_of_particle, piece_rate_, h, piece_moments_);
}

template <class Real>
void SolverT<Real>::update_normals(SoftBodyT<Real>& body) {
    if constexpr (std::is_same_v<Real, float>) {
        const size_t n = body.particles.size();
        body.normals.resize(n);
        for_range(n, k_particle_grain, [&](size_t b, size_t e) { sim::update_normals(body.rings, body.particles.x, body.normals, b, e); });
    }
}

template <class Real>
void SolverT<Real>::settle(SoftBodyT<Real>& body, const SolverSettings& s, float dt) {
    touching_.clear();
    // The pairs wake a sleeping piece beside a moving one and keep a piece awake beside one that
    // moved fast: one pass over the candidates a frame, against their projection every sweep.
    if (s.contact.enabled && s.sleep.enabled && !body.sleep.resting()) contact_.touching_pieces(body, touching_);
    // The pieces that give under contact (sim/sleep.h): those of no cluster, or of a soft one.
    piece_gives_.clear();
    if (!touching_.empty()) {
        piece_gives_.assign(body.pieces, 1);
        for (const ShapeCluster& c : body.shapes) {
            if (stiffness_of(c, s.shape_stiffness) < k_rigid_response_stiffness) continue;
            for (const uint32_t i : c.particles)
                if (body.piece_of_particle[i] < body.pieces) piece_gives_[body.piece_of_particle[i]] = 0;
        }
    }
    update_sleep<Real>(body, touching_, s.sleep, dt, piece_gives_);
}

template <class Real>
void SolverT<Real>::run(Stage stage, SoftBodyT<Real>& body, const SolverSettings& s, Real h, const Colliders& colliders,
                        const DragConstraint& drag) {
    // Nothing moves while every piece sleeps, and nothing need be computed; what acts on the body
    // wakes it before the frame's stages run.
    if (body.sleep.resting() && stage != Stage::sleep) return;
    switch (stage) {
    case Stage::forces: begin_substep(body, s, h); break;
    case Stage::distance: project_distance(body, body, s, h); break;
    case Stage::volume:
        if (s.volume) project_volume(body, s, h);
        break;
    case Stage::shape: project_shape(body, body, s, h); break;
    case Stage::drag: apply_drag(body, drag); break;
    case Stage::collide: collide(body, colliders); break;
    case Stage::find_contacts: find_contacts(body, s); break;
    case Stage::contact: project_contacts(body, s); break;
    case Stage::velocities: end_substep(body, s, h); break;
    case Stage::normals: update_normals(body); break;
    case Stage::sleep: settle(body, s, float(h) * float(s.substeps)); break;
    }
}

template <class Real>
StageTimings SolverT<Real>::step(SoftBodyT<Real>& body, float dt, const SolverSettings& settings, const Colliders& colliders,
                                 const DragConstraint& drag) {
    // Pieces stacked at the last search step this frame in the contact's substeps: resting on
    // each other they sink in at one step a frame (sim/contact.h). A body alone pays nothing.
    SolverSettings s = settings;
    if (s.tuned_substeps == 0) s.tuned_substeps = settings.substeps;
    s.substeps = frame_substeps(settings, body, contact_, dt, k_max_sweeps);
    if (schedule_.empty() || schedule_iterations_ != s.iterations || schedule_substeps_ != s.substeps) {
        schedule_ = frame_schedule(s);
        schedule_iterations_ = s.iterations, schedule_substeps_ = s.substeps;
    }
    StageTimings t;
    const Real h = Real(dt) / Real(s.substeps);
    for (const ScheduledStage& stage : schedule_) {
        const core::Stopwatch clock;
        run(stage.stage, body, s, h, colliders, drag);
        t.add(stage_group(stage.stage), clock.elapsed_ms());
    }
    return t;
}

template class SolverT<float>;
template class SolverT<double>;

} // namespace pbdsplat::sim
