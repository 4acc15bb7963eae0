#pragma once
// One frame of Stage A, in the paper's order (section 5.2): external forces, prediction,
// I iterations of [distance constraints, overpressure constraint] (+ collisions, contact between
// moving surfaces and drag),
// velocities from positions, normals. Each stage is its own function over compact arrays.
#include <cstdint>

#include "core/names.h"
#include "core/thread_pool.h"
#include "sim/colliders.h"
#include "sim/contact.h"
#include "sim/deform_damping.h"
#include "sim/fold_guard.h"
#include "sim/constraints.h"
#include "sim/schedule.h"
#include "sim/sleep.h"
#include "sim/soft_body.h"
#include "sim/volume.h"

namespace pbdsplat::sim {

enum class SolverMode {
    paper,  // PBD, stiffness in (0,1] corrected for the iteration count
    xpbd,   // compliance-based, iteration-count independent stiffness
};
inline constexpr core::EnumName<SolverMode> k_solver_mode_names[] = {{SolverMode::paper, "paper"}, {SolverMode::xpbd, "xpbd"}};

struct SolverSettings {
    SolverMode mode = SolverMode::paper;
    uint32_t iterations = 5;  // I
    uint32_t substeps = 1;    // S: each frame is S steps of dt / S
    // The substeps the stiffnesses below are meant at: the scene's, where contact steps a frame
    // finer (0: `substeps`). See raised_scale.
    uint32_t tuned_substeps = 0;
    Vec3f gravity{0.0f, -9.81f, 0.0f};
    float damping = 0.0f;             // velocity decay rate, 1/s
    float deform_damping = 0.0f;      // 1/s: decay of each piece's motion apart from its rigid motion (sim/deform_damping.h)
    float stretch_stiffness = 1.0f;   // PBD, per frame's worth of iterations
    float volume_stiffness = 1.0f;    // PBD
    // Shape matching toward each piece's rest shape (bodies built with shape_matching): PBD
    // stiffness per frame in [0, 1], 0 = off. XPBD uses `shape_compliance` when it is > 0.
    float shape_stiffness = 0.0f;
    float shape_compliance = 0.0f;
    bool volume = true;               // project the body's volume constraints
    ContactSettings contact;          // between the pieces of the body, and of a piece with itself
    SleepSettings sleep;              // pieces at rest held still (sim/sleep.h)
};

// PBD holds a body the more firmly the more substeps a frame takes: a 0.9 m balloon (stiffness
// 1, no shape matching) rests at 0.57 of its height at one substep and 0.82 at four, one of shape
// 0.05 at 0.73 and 0.86. Where contact raised a frame's substeps past those the scene is tuned
// at (stacked pieces, sim/approach.h), a soft body lying in the softer shape sprang to the firmer
// one within a frame: a balloon squashed under a box threw itself and the box 4 m up (2 J -> 27
// J). So in a raised frame a soft body (shape stiffness under k_rigid_response_stiffness) projects
// its edges at (tuned / substeps)^(k_raised_edges x fade) of their stiffness and its shape
// matching at (tuned / substeps)^(k_raised_shape x fade), which keeps its resting shape as the
// raise finds it (measured, docs/BENCHMARKS.md "Contact"); `fade` falls from 1 when the
// substeps rise to 0 with time constant k_raise_firming, so that it takes on the firmness of
// the finer steps (what holds a heavy ball in a soft box's dent) slowly, not in a frame: measured,
// at 0.5 s the box on a balloon of shape 0.05 still gained 40 %, at 2 s the ball rolled round the
// dent for good. A stiff body's shape matching stands it either way, and firmness is what a
// stack's substeps are for. XPBD is left as it is, though its hard constraints unconverged
// depend on the step as PBD's do (the same box: 27 J at compliance 0).
inline constexpr float k_raised_edges = 1.5f;
inline constexpr float k_raised_shape = 1.0f;
inline constexpr float k_raise_firming = 1.0f;  // s
float raised_scale(const SolverSettings& s, float shape_stiffness, float exponent, float fade);

// Milliseconds per stage of the last step, named as in the paper's Tables 3 and 4.
struct StageTimings {
    double apply_forces = 0.0;       // external forces and prediction
    double constraints = 0.0;        // distance, volume, shape, collisions, drag
    double integrate_normals = 0.0;  // velocities and normals
    double total() const { return apply_forces + constraints + integrate_normals; }
    void add(StageGroup g, double ms) {
        (g == StageGroup::apply_forces ? apply_forces : g == StageGroup::constraints ? constraints : integrate_normals) += ms;
    }
};

// Constraint sweeps (iterations x substeps) a frame may take: a scene is refused past it, and the
// substeps raised for contact stay within it.
inline constexpr uint32_t k_max_sweeps = 256;

// Validates the settings: a clear reason for an impossible value (I = 0, NaN gravity, ...).
core::Status validate(const SolverSettings& s);

template <class Real>
class SolverT {
public:
    // With a pool, each stage splits its arrays over the threads: particles in ranges, distance
    // constraints colour by colour, the volume constraint in fixed blocks. The result does not
    // depend on the thread count.
    explicit SolverT(core::ThreadPool* pool = nullptr) : pool_(pool) { contact_.set_pool(pool), folds_.set_pool(pool); }

    // Advances `body` by `dt` seconds (one frame): frame_schedule(settings) (sim/schedule.h),
    // stage by stage. `drag` may be inactive. Normals are updated for float bodies (the ones
    // that are rendered).
    StageTimings step(SoftBodyT<Real>& body, float dt, const SolverSettings& settings, const Colliders& colliders,
                      const DragConstraint& drag);

    // One stage of the schedule, `h` the substep length: what step() runs for each entry, and
    // what each frame-graph pass runs for its own.
    void run(Stage stage, SoftBodyT<Real>& body, const SolverSettings& s, Real h, const Colliders& colliders,
             const DragConstraint& drag);

    // The stages themselves. forces = begin_substep, velocities = end_substep. Those that move
    // only the state take the body's parts apart, the structure (or caches) they read const.
    void begin_substep(SoftBodyT<Real>& body, const SolverSettings& s, Real h);
    // distance_k_ for this substep: each constraint its model's stretch stiffness per projection.
    void stretch_per_constraint(const SoftBodyT<Real>& body, const SolverSettings& s);
    // raise_fade_ for this substep (raised_scale).
    void fade_raise(const SolverSettings& s, Real h);
    void project_distance(const BodyStructureT<Real>& structure, BodyStateT<Real>& state, const SolverSettings& s, Real h);
    void project_volume(SoftBodyT<Real>& body, const SolverSettings& s, Real h);
    // project_volume's rigid moves per slot (volume_nudge), from totals_ and steps_: none for a
    // pressed piece; a piece's mass moments summed at its first unbalanced projection a substep.
    void rigid_nudges(const SoftBodyT<Real>& body, const VolumeLayout& l);
    void project_shape(BodyCachesT<Real>& caches, BodyStateT<Real>& state, const SolverSettings& s, Real h);
    void apply_drag(BodyStateT<Real>& state, const DragConstraint& drag);
    void collide(BodyStateT<Real>& state, const Colliders& colliders);
    void find_contacts(SoftBodyT<Real>& body, const SolverSettings& s);
    void project_contacts(SoftBodyT<Real>& body, const SolverSettings& s);
    const ContactSolverT<Real>& contact() const { return contact_; }
    const FoldGuardT<Real>& folds() const { return folds_; }
    void end_substep(SoftBodyT<Real>& body, const SolverSettings& s, Real h);
    void update_normals(SoftBodyT<Real>& body);
    // After a frame of `dt`: islands of pieces at rest fall asleep, disturbed ones wake.
    void settle(SoftBodyT<Real>& body, const SolverSettings& s, float dt);

private:
    // fn(begin, end) over [0, n), split over the pool when n reaches `grain`.
    template <class Fn>
    void for_range(size_t n, size_t grain, const Fn& fn);

    core::ThreadPool* pool_ = nullptr;
    std::vector<ScheduledStage> schedule_;  // for the iterations and substeps below
    uint32_t schedule_iterations_ = 0, schedule_substeps_ = 0;
    Vec4ArrayT<Real> scratch_;  // volume gradients
    std::vector<BlockSums> sums_;     // per block
    std::vector<VolumeSums> totals_;  // per slot
    std::vector<Real> steps_;       // per slot
    std::vector<RigidNudge<Real>> nudges_;  // per slot: volume_nudge
    std::vector<uint8_t> wanted_;             // per slot: its mass moments are summed now
    std::vector<BlockMoments> moment_blocks_;
    std::vector<MassMoments> moments_;
    std::vector<std::pair<uint32_t, uint32_t>> pressed_pairs_;  // find_contacts' touching pieces
    VolumeSlots slots_;
    ContactSolverT<Real> contact_;  // this substep's candidates
    bool stiff_contact_ = false;    // this substep: some cluster answers contact as a solid
    FoldGuardT<Real> folds_;        // and a skin's folds through its own neighbourhood
    std::vector<std::pair<uint32_t, uint32_t>> touching_;  // pieces in contact, for sleep
    std::vector<uint8_t> piece_gives_;                     // per piece: soft under contact, for sleep
    std::vector<float> piece_rate_;                        // deform_damping per piece
    std::vector<Real> model_keep_;                         // velocity kept per model a substep (own damping)
    std::vector<Real> distance_k_;  // PBD stiffness per projection, per distance constraint, where models name their own
    float raise_fade_ = 0.0f;       // raised_scale's fade: 1 as the substeps rise, toward 0 after
    uint32_t raise_substeps_ = 0;   // the raised substeps it faded at (0: not raised)
    std::vector<PieceMoments> piece_moments_;
};
using Solver = SolverT<float>;

} // namespace pbdsplat::sim
