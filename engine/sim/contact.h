#pragma once
// Contact between everything that moves: a particle against the surface of another piece of its
// body (what a cut or a tear made, or another model of the scene), and against its own piece
// away from its neighbourhood (a fold, a crumpled balloon). The surface is the piece's triangles
// plus the cut faces that close its cap loops (each loop spanned by its least-area triangles as
// it lay when first seen: a concave cross-section is covered where it is solid and nowhere else,
// and a face cut again is two faces folded along the new cut), so a piece cut off rests on the
// cut face of the piece below instead of falling into it.
//
// Each substep finds candidate (particle, triangle) pairs after prediction, through a hash grid
// of the particles (keeping the last search's while no particle has moved half the slack since;
// where some pieces have, and they hold at most half the particles, searching those pieces
// alone against everything and keeping the rest's pairs among themselves; none for a body of
// one piece without self-contact, which has nothing to meet); each
// iteration then projects them as one-sided PBD constraints
//   side * (x_p - q(a, b, c)) . n  >=  thickness
// with Coulomb friction on the relative motion since the substep began. The side is read at the
// substep's start, so a particle that was in front of a triangle stays in front however far it
// moved since (no tunnelling through a surface at any speed the hash's sweep covers); against a
// closed piece (one with a volume constraint) it is always the outside, so a particle that ended
// up shallowly inside is pushed out, except for a part that lay wholly inside that piece at load
// (a stone in a fruit, sim/enclosure.h): that one is kept inside.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "core/thread_pool.h"
#include "sim/colliders.h"
#include "sim/rigid_response.h"
#include "sim/soft_body.h"

namespace pbdsplat::sim {

// Self-contact is off unless a scene asks for it: against the paper's hard global volume
// constraint it fights a shell crushed below its folds' room (an icosphere deflated to 5 % of
// its volume inverts instead of crumpling, a model landing on the ground loses 15 % of its
// volume), so it is for open sheets and soft balloons that are meant to fold.
inline constexpr bool k_self_contact_default = false;

// Substeps a frame runs while pieces are stacked (a piece on another's cut face, a model on
// another). PBD's error per step grows with the step squared: a cut bunny's top half, resting on
// its bottom half at 5 iterations, sank 34 edges into it within 2 s at one step a frame (10
// iterations: the same; 20: 3 edges), 3.4 edges at 2 substeps, 0.09 at 4, where its height held
// at 0.98 of the uncut bunny's (docs/BENCHMARKS.md, "Contact"). Soft constraints keep their
// stiffness per frame; hard ones (stiffness 1) converge further in the extra sweeps.
inline constexpr uint32_t k_contact_substeps_default = 4;

struct ContactSettings {
    bool enabled = true;     // a user expects the pieces of a cut to be solid
    bool self = k_self_contact_default;  // a piece against itself, away from its neighbourhood (folds)
    bool folds = true;       // a soft skin against its own neighbourhood, where it folds through it (sim/fold_guard.h)
    bool fold_edges = false; // and its edges against each other there (sim/fold_edges.h): fewer crossings, more cost
    uint32_t substeps = k_contact_substeps_default;  // a frame's substeps while pieces are stacked (at least the solver's)
    bool approach = true;    // finer substeps while stiff pieces close in fast (sim/approach.h)
    float thickness = 0.0f;  // metres kept between a particle and a surface; 0: auto (see below)
    Friction friction;
};

// The lengths contact works with, from the body's mean rest edge length L.
struct ContactScale {
    float edge = 0.0f;       // L
    float thickness = 0.0f;  // the settings' value, or k_auto_thickness x L
    float margin = 0.0f;     // how deep inside a closed piece a particle may be and still be pushed out
    float exclusion = 0.0f;  // rest-space radius of a particle's own neighbourhood, never in contact with it
    float slack = 0.0f;      // how much further the search reaches, so its candidates last
};
// A quarter of an edge: far below the splats' size (about half an edge), so pieces resting on
// each other show no gap, and enough that a resting contact's iteration error stays outside.
inline constexpr float k_auto_thickness = 0.25f;
ContactScale contact_scale(float mean_rest_edge, const ContactSettings& s);
// Mean rest length of the body's live distance constraints (0 without any).
template <class Real>
float mean_rest_edge(const SoftBodyT<Real>& body);

// Whether a cap loop encloses a face worth resting on (a cut's cross-section), not a slit (a
// tear's, whose two sides lie on each other at rest): the least area spanning the loop against
// its perimeter squared, at least 0.002 (a circle's 1 / (4 pi) = 0.08, a square's 0.06, a 10:1
// rectangle's 0.02, a 100:1 one's 0.0025; a slit's 0). A thin slice a later cut takes off a
// piece's edge is a face: judged a slit at 0.02, a ball cut by three planes left two hollow
// slivers, and a bunny cut by ten random planes shell-like shards. A loop that runs over two
// planes (a cut across the face an earlier cut left) counts both planes' area; its projected
// (Newell) area alone made such a face a slit.
// Judged in rest space where `rest` holds every particle's rest position: a face crumpled by the
// pieces' motion would otherwise come and go, and what rested on it fall through while it was
// gone. Cubic in the loop's corners (mesh::triangulate_least_area): callers keep the answer.
template <class Real>
bool encloses_face(const std::vector<uint32_t>& loop, const Vec4ArrayT<Real>& x, const std::vector<Vec3f>& rest);

// The triangles spanning a face's loop (corner triples into `loop`, wound like it), as it lies in
// `x`: mesh::triangulate_across_older, the loop's particles found in `older` (sorted: the
// particles of every loop known before the change that made this one) taken as the older face's
// corners, so a face a second cut crossed folds along the cut (`parts`: as there).
template <class Real>
std::vector<std::array<uint32_t, 3>> face_triangles(const std::vector<uint32_t>& loop, const Vec4ArrayT<Real>& x,
                                                    std::span<const uint32_t> older, std::vector<uint8_t>* parts = nullptr);
// The sorted particles of these loops, for face_triangles.
std::vector<uint32_t> loop_particles(std::span<const std::vector<uint32_t>* const> loops);

// A particle keeps at most this many candidates, its nearest (by height over the triangle's plane
// plus distance beside it). In the random-cut stress test's heap of a thousand crushed flakes a
// particle had up to 900 triangles within reach, and the search and every iteration paid for each
// (a second a frame at 11k particles, 0.06 s with the limit). A particle on a surface has a few;
// over a cut face's fan of sliver triangles, where the pile scene's stack meets, up to 130, of
// which those it is over are the nearest.
inline constexpr uint32_t k_max_candidates = 32;

// One candidate: particle `particle` against surface triangle `triangle` (an index past the
// body's triangles names a cut face's triangle), kept on side `side` of it.
struct Contact {
    uint32_t particle;
    uint32_t triangle;
    float side;
    float thickness;  // the scale's, or less where the two started closer at rest
    float key = 0.0f; // its distance when found (height plus distance beside): the nearest are kept
};

template <class Real>
class ContactSolverT {
public:
    // After prediction (x_prev: the substep's start, x: predicted): the candidates of this substep.
    // `shape_stiffness`: the settings', for the clusters whose body names none of its own; a
    // cluster below k_rigid_response_stiffness answers particle by particle.
    void find(const SoftBodyT<Real>& body, const ContactSettings& s, float shape_stiffness = 1.0f);
    // One sweep over the candidates (call every iteration): those answered particle by particle
    // as each particle's mean correction (project_soft). With `stiff_bodies`, a particle of a
    // shape cluster answers with its whole cluster (sim/rigid_response.h).
    void project(SoftBodyT<Real>& body, const ContactSettings& s, bool stiff_bodies = false);

    const std::vector<Contact>& contacts() const { return contacts_; }
    // The sleeping pieces a sweep pressed harder than a resting contact presses (deeper than the
    // thickness), each once: they must wake and give, or the awake side alone takes the whole
    // push, against its own constraints, sweep after sweep (sim/sleep.h).
    const std::vector<uint32_t>& pressed_sleepers() const { return pressed_sleepers_; }
    void clear_pressed_sleepers() { pressed_sleepers_.clear(); }
    // The pieces the candidates bring together (a particle's and its triangle's), each pair once
    // with the smaller first, appended to `out`.
    void touching_pieces(const SoftBodyT<Real>& body, std::vector<std::pair<uint32_t, uint32_t>>& out) const;
    // Every patch against every triangle group instead of through the hash grid (the same pairs:
    // what the tests compare the broad phase with).
    void set_brute_force(bool on) { brute_force_ = on; }
    // Threads for the search (the caller's pool; null: the calling thread alone). The candidates
    // do not depend on it.
    void set_pool(core::ThreadPool* pool) { pool_ = pool; }
    // Which way is up (against gravity; zero: no stacks).
    void set_up(const Vec3f& up) { up_ = up; }
    // Into how many chunks the last search split its patches (1: it ran on the calling thread).
    size_t search_chunks() const { return chunk_.size(); }
    const ContactScale& scale() const { return scale_; }
    // Searches run (a find that kept the last candidates runs none), and of them those of the
    // moved pieces alone.
    size_t searches() const { return searches_; }
    size_t partial_searches() const { return partial_searches_; }
    // Whether the last search found a piece within reach of another's cut face, or one model
    // within reach of another: what stacks, and needs the contact substeps.
    bool stacked() const { return stacked_; }

private:
    struct CutFace {  // one cap loop: its cut face
        uint32_t first = 0, count = 0;  // into face_vertices_
        uint32_t piece = 0;
        Vec3f normal = Vec3f::Zero();  // the loop's (Newell's), out of its piece
        bool cut = false;              // a cut's face (not one of the model's own holes)
    };
    // The two sides of a cut face, matched rim particle by rim particle (the copies a cut made of
    // one vertex, at one rest place): kept from passing through each other along the faces'
    // normal, never pulled together.
    // A piece resting on a cut face bears on its rim, which the face's triangles, tilting as the
    // rim bends, cannot hold alone.
    struct SeamPair {
        uint32_t a, b;          // particles, of two pieces
        uint32_t face_a, face_b;  // their loops' faces
    };
    std::vector<SeamPair> seam_pairs_;
    RigidResponseT<Real> rigid_;
    std::vector<uint32_t> touch_;  // the clusters a substep's candidates move
    bool rigid_ready_ = false;     // their frames taken this substep
    // Per candidate, then per seam pair: the clusters its sides answer with, this substep.
    void touch_clusters(const SoftBodyT<Real>& body);
    // The clusters the two sides of a pair answer with (RigidResponse::k_none: each particle alone).
    struct Sides {
        uint32_t particle = RigidResponseT<Real>::k_none, surface = RigidResponseT<Real>::k_none;
        bool any() const { return particle != RigidResponseT<Real>::k_none || surface != RigidResponseT<Real>::k_none; }
    };
    Sides sides_of(uint32_t i, const std::array<uint32_t, 3>& corners) const;
    std::vector<Sides> pair_sides_;
    // A heavy piece on a light one. Each pair's correction is split by inverse mass, so where the
    // upper piece's particles weigh many times the lower's, the lower takes nearly all of it and
    // its own constraints, a fraction of the way each iteration, cannot carry the weight: a 20 kg
    // ball on a 0.5 kg box (24x a particle) sank into it and both slid off. In such a pair the
    // lower side's inverse mass is scaled down toward the upper's, fully once their pieces' centres
    // lie k_lift_span edges apart along up_ (so side by side, nothing changes, and a collision
    // between equals keeps its momentum): the 24x ball and a 600x one rest on the box (penetration
    // 0, asleep). A light piece on a heavy one, or pieces of like weight (a cut's), are unchanged.
    struct Lift {
        float particle = 1.0f, surface = 1.0f;  // scales on the two sides' inverse masses
    };
    static constexpr float k_lift_span = 2.0f;
    // Within this ratio of mean particle masses, pieces are of like weight: unchanged (a stiff
    // ball 2.4x and 6x a box's rested without the lift; computing it for every pair of a cut's
    // nearly equal pieces cost the pile 7-16 % of Stage A).
    static constexpr float k_lift_ratio = 2.0f;
    // Pushes particle i `depth` along the unit `n` off the point of weights `u` on `corners`, each
    // side alone or with its cluster, then Coulomb friction on their relative motion since the
    // substep began. Of the depth, `overlap` was there when the substep began (two sides a cut
    // just made, lying on each other within the thickness): it is taken out of the start
    // positions too. Pushed out as motion, it flung a cut bunny's hindquarters off at 2 m/s.
    void separate(ParticlesT<Real>& p, const ContactSettings& s, uint32_t i, const std::array<uint32_t, 3>& corners,
                  const std::array<float, 3>& u, Sides sides, const Vec3f& n, float depth, float overlap, Lift lift);
    // A candidate of which a side answers with its cluster.
    // Returns the depth it pushed out (0: none).
    float project_rigid(ParticlesT<Real>& p, const ContactSettings& s, const Contact& ct, const std::array<uint32_t, 3>& corners, Sides sides,
                        Lift lift);
    Vec3f up_ = Vec3f::Zero();
    std::vector<float> piece_height_;  // each piece's mean height along up_, this substep
    std::vector<float> piece_weight_;  // its particles' mean mass (0: it holds a pinned one)
    std::vector<uint32_t> piece_count_;
    bool heights_ready_ = false;
    void take_heights(const SoftBodyT<Real>& body);
    Lift lift(const SoftBodyT<Real>& body, uint32_t particle, uint32_t corner) const;
    std::vector<uint32_t> pressed_sleepers_;
    // A push `depth` deep between particle i and `corners`: a sleeping side pressed past the
    // scale's thickness (not the pair's, which is 0 across a cut) joins pressed_sleepers_.
    void note_push(const SoftBodyT<Real>& body, uint32_t i, const std::array<uint32_t, 3>& corners, float depth);
    std::vector<uint8_t> on_rim_;  // per particle: on a loop of faces_
    void build_seam_pairs(const SoftBodyT<Real>& body);
    void project_seams(SoftBodyT<Real>& body, const ContactSettings& s, bool rigid);
    struct FaceTriangle {
        uint32_t face;
        uint32_t a, b, c;  // particles of its loop, wound as the loop (out of the piece)
        uint32_t chunk;    // its broad-phase group, past the patches
    };
    static constexpr uint32_t k_fan_chunk = 8;
    uint32_t face_chunks_ = 0;
    struct Corners {
        uint32_t ia, ib, ic;
        const CutFace* face;  // the cut face a cap triangle belongs to; null for the body's triangles
    };
    Corners corners_of(const SoftBodyT<Real>& body, uint32_t triangle) const;
    // A candidate that both sides answer particle by particle: its push and friction summed into
    // soft_delta_ and applied as each particle's mean once the sweep has seen every candidate
    // (Jacobi), so that no order among them is preferred. Applied one at a time, the result hangs
    // on their order: a ball resting in the dent of a soft box rolls out of it one way, and the
    // other way with the candidates reversed; without friction it slides off within a second.
    void project_soft(const SoftBodyT<Real>& body, const ContactSettings& s, const Contact& ct, const Corners& corners);
    void add_soft(uint32_t i, const Vec4<Real>& d, const Vec4<Real>& settle);
    void apply_soft(ParticlesT<Real>& p);
    Vec4ArrayT<Real> soft_delta_, soft_settle_;  // summed moves of x and of x_prev
    std::vector<uint32_t> soft_count_;  // per particle: the candidates that moved it this sweep
    std::vector<uint32_t> soft_touched_;
    // Each cap loop's triangles (loop positions), made when the loop first appears: a loop keeps
    // its face while it lives, as a cut made it, however the piece deforms since.
    struct CapFace {
        std::vector<uint32_t> loop;
        std::vector<std::array<uint32_t, 3>> triangles;
        bool encloses = false;  // a face, not a slit (encloses_face)
        bool used = false;
    };
    std::vector<CapFace> cap_faces_;
    const CapFace& cap_face(const std::vector<uint32_t>& loop, const SoftBodyT<Real>& body);
    void build_faces(const SoftBodyT<Real>& body);
    void update_faces(const ParticlesT<Real>& p);

    ContactScale scale_;
    std::vector<Contact> contacts_;
    std::vector<CutFace> faces_;
    std::vector<uint32_t> face_vertices_;
    std::vector<FaceTriangle> face_triangles_;
    std::vector<uint8_t> closed_;  // per piece
    void update_origins(const SoftBodyT<Real>& body);
    void build_patches(const SoftBodyT<Real>& body);
    void test_pair(const SoftBodyT<Real>& body, uint32_t patch, uint32_t group, float r_ex2, std::vector<Contact>& out);
    // A particle's own neighbourhood (in rest space) never touches it: on its own piece (nor does
    // its own cap, which closes it along its rim); across a cut or tear, on the other side's
    // triangles (the two sides start on each other, and pushed apart the seam's edges would
    // stretch until a tear ran from it: the cut face's cap carries their contact); and across two
    // parts of one model that lie on each other at load (a teapot's lid, suzanne's eyes: their
    // relative place changes with the shell's pressure, and pushed apart they tear it).
    // The other side of a cut of a closed piece is the exception for the particles of a cut
    // face's rim: its shell is met at no thickness (the gap the seam had), from outside only, so
    // that a rim slipping off the face it rests on cannot come back in through that piece's wall
    // beside the face, and a seam at rest is not pushed apart. Only the rim's: a soft balloon's
    // two halves wrinkle against each other beside the seam, and met there they push themselves
    // apart.
    struct Neighbourhood {
        bool skip = false;  // never in contact
        bool near = false;  // of its piece, the other side of its cut or another part of its model
        bool seam = false;  // a rim particle against the other side's shell: met at no thickness
    };
    Neighbourhood neighbourhood_of(const SoftBodyT<Real>& body, uint32_t i, uint32_t pi, uint32_t piece, const Corners& tk, bool closed,
                                   float r_ex2) const;
    // Pieces that were closer than the thickness at rest (the two sides of a cut, which start on
    // each other; two models placed with a small gap) keep the gap they had: pushing them apart
    // at the first step would throw them, or pull a seam's edges apart until a tear ran from it.
    // False: the pair started inside each other, and is left alone.
    bool rest_gap(const SoftBodyT<Real>& body, uint32_t i, const Corners& tk, float side, float& thickness) const;
    // The steps of find(), in order.
    // What the last search's candidates are worth now: every pair (`hold`; the pieces that moved
    // past the slack but lie far from every other, `away_`, have their stale candidates dropped),
    // the pairs between pieces that did not move (`moved_only`: the pieces in `away_` are searched
    // again against everything, the rest keep their candidates among themselves), or nothing.
    enum class Worth { hold, moved_only, none };
    Worth candidates_hold(const SoftBodyT<Real>& body, const ContactSettings& s);
    bool moved_pieces_apart(const SoftBodyT<Real>& body);
    std::vector<uint8_t> away_;                    // per piece, from candidates_hold
    // A search of the moved pieces alone. A pair it finds has one side where it now anchors and
    // the other up to half the slack from its older anchor, so up to the whole slack from here:
    // it reaches half a slack further than a full search, whose pairs are both freshly anchored.
    bool partial_ = false;
    float extra_reach_ = 0.0f;
    std::vector<uint32_t> held_start_;   // per patch, CSR into held_: the candidates it keeps
    std::vector<Contact> held_, held_sorted_;  // the latter: scratch for sorting them by patch
    void hold_unmoved(const SoftBodyT<Real>& body);
    std::vector<Eigen::AlignedBox3f> swept_box_;  // scratch: each piece's path this substep
    void box_patches(const SoftBodyT<Real>& body, float reach);
    void group_triangles(const SoftBodyT<Real>& body);
    void build_grid(const SoftBodyT<Real>& body);
    void search_pairs(const SoftBodyT<Real>& body);
    // After a search: whether pieces are stacked, and where the searched particles anchor.
    void note_search(const SoftBodyT<Real>& body);
    // What one chunk of the patches finds, and the groups it has visited for its current patch.
    struct ChunkScratch {
        std::vector<Contact> contacts;
        std::vector<uint32_t> seen;
    };
    std::vector<ChunkScratch> chunk_;
    // Fewer patches than this a chunk cost more to hand out than they take to search.
    static constexpr uint32_t k_patches_per_chunk = 64;
    void search_patches(const SoftBodyT<Real>& body, uint32_t first, uint32_t last, ChunkScratch& c);
    core::ThreadPool* pool_ = nullptr;
    // The hash grid's cells a box meets (false: it is wider than k_span cells, and stays out of
    // the grid), and a visit of each of them.
    static constexpr int k_span = 8;
    bool cell_range(const Eigen::AlignedBox3f& b, Eigen::Vector3i& lo, Eigen::Vector3i& hi) const;
    template <class Fn>
    void each_cell(const Eigen::Vector3i& lo, const Eigen::Vector3i& hi, const Fn& fn) const;
    bool meets_another(const Eigen::AlignedBox3f& b, uint32_t piece, size_t pieces) const;
    float inv_cell_ = 1.0f;
    uint32_t table_ = 16;
    bool by_piece_ = false;

    std::vector<uint32_t> patch_of_, patch_start_, patch_particles_;  // rest-space patches, CSR
    float patch_edge_ = 0.0f;
    size_t patch_pieces_ = 0;
    std::vector<Vec3f> now_, then_;  // positions in float, predicted and at the substep's start
    std::vector<Eigen::AlignedBox3f> particle_box_, rest_box_, group_box_;  // per patch; per triangle group
    std::vector<uint32_t> patch_piece_;  // per group: its piece
    std::vector<Eigen::AlignedBox3f> piece_box_;  // per piece: its patches' and groups' boxes
    std::vector<uint8_t> in_play_;       // per group: its box meets another piece's
    // Per particle, the part (connected component at load) and the model it came from: the two
    // sides of a cut are one part, a teapot's lid and body two parts of one model.
    std::vector<uint32_t> part_, model_;
    std::vector<Eigen::AlignedBox3f> triangle_box_;  // swept, per entry of group_triangles_
    std::vector<uint32_t> group_start_, group_triangles_, big_groups_;
    std::vector<uint32_t> cell_start_, cell_particles_;
    std::vector<uint32_t> entry_piece_, run_end_;  // per entry of cell_particles_: its group's piece, where that piece's run ends
    std::vector<uint32_t> kept_;    // per particle: its candidates so far
    std::vector<uint32_t> slot_;    // per particle, k_max_candidates: their places in contacts_
    std::vector<float> slot_key_;   // and their distances
    // The distance of the particle's farthest kept candidate once it has them all (else infinity):
    // a triangle whose plane is as far from it is no nearer.
    float farthest_kept(uint32_t particle) const;
    // Adds `c` among its particle's candidates if it is among the k_max_candidates nearest by key.
    void keep(std::vector<Contact>& out, const Contact& c);
    std::vector<uint32_t> cursor_;  // fill position per bucket while a counting sort fills it
    bool brute_force_ = false;
    size_t searches_ = 0, partial_searches_ = 0;
    std::vector<Vec3f> anchor_;  // per particle: where it was at the last search that searched its piece
    size_t anchor_triangles_ = 0, anchor_pieces_ = 0;
    bool self_ = false;
    bool stacked_ = false;
};
using ContactSolver = ContactSolverT<float>;

} // namespace pbdsplat::sim
