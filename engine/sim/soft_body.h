#pragma once
// One deformable body: its particles, its surface triangles and its constraints, built from a
// repaired mesh; its structure, state and caches apart (below). The solver stages operate on it; the topology stage (cuts) is the only other
// code that changes it. SoftBody is the float body the engine runs; SoftBodyT<double> exists
// for accuracy references.
#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "core/result.h"
#include "mesh/surface_texcoord.h"
#include "mesh/triangle_mesh.h"
#include "sim/constraint_order.h"
#include "sim/constraints.h"
#include "sim/integrate.h"
#include "sim/particles.h"
#include "sim/shape.h"
#include "sim/sleep.h"
#include "sim/volume.h"

namespace pbdsplat::sim {

enum class MassMode { area, uniform };

struct SoftBodyDesc {
    float total_mass = 1.0f;      // kg, spread over the particles
    MassMode mass_mode = MassMode::area;
    float stretch_compliance = 0.0f;  // per distance constraint (XPBD)
    bool volume = true;            // one volume constraint per component
    float pressure = 1.0f;         // k of every volume constraint
    float volume_compliance = 0.0f;
    bool shape_matching = false;   // one shape-matching cluster per connected piece (and the parts welded to it)
    bool reorder = true;           // Morton-order particles for cache locality
};

// A body in three parts, as a reader needs them: what it is made of (written when it is built
// and by the topology stage), where it is (written by the solver every step) and what is derived
// from the two (kept to save recomputing it). SoftBodyT is all three; a function that needs only
// one part takes only that part.

// What the body is made of: its particles' rest and origin, its triangles, its constraints and
// its pieces. Only the body's builder and the topology stage (cuts, tears) change it, except the
// volume constraints' pressure and air, which the scene's timeline and a leak change each step.
template <class Real>
struct BodyStructureT {
    std::vector<mesh::Triangle> triangles;
    std::vector<DistanceConstraint> distance;  // grouped by colour; may hold dead slots (see constraint_order.h)
    DistanceGroups distance_groups;            // colour c holds distance[start[c], start[c + 1])
    // Parts of one model that touch at rest, held together (sim/weld.h); not mesh edges.
    std::vector<DistanceConstraint> welds;
    std::vector<VolumeConstraint> volumes;  // one per piece that holds air, naming its piece, in piece order
    // The connected piece (of `triangles`, through shared vertices) of every particle, ids
    // 0 .. pieces - 1, k_no_piece for a particle in no triangle. Topology edits keep both: a
    // split relabels the particles of the new pieces, and ids never change otherwise.
    std::vector<uint32_t> piece_of_particle;
    size_t pieces = 0;
    bool shape_matching = false;        // one cluster per piece (BodyCachesT::shapes)
    std::vector<Vec3f> rest_positions;  // rest state (new edges take rest lengths from it)
    std::vector<Vec3f> colors;          // per-particle colours from the mesh file; empty if none
    // Per particle, where a textured model's texture lies at it (scene/stages/paint.h); empty
    // unless a model is textured and the particles are drawn.
    std::vector<mesh::SurfaceTexcoord> texcoords;
    // The model each particle was loaded from (a scene's [model] and [[bodies]]; a particle a
    // topology edit adds takes its source's). make_soft_body makes the whole mesh one model.
    std::vector<uint32_t> model_of_particle;
    // Per model, its own shape stiffness (negative: the solver settings'); empty: every model
    // the settings'. Each shape cluster takes its model's (ShapeCluster::own_stiffness).
    std::vector<float> model_shape_stiffness;
    // Per model, its own velocity decay rate in 1/s (negative: the solver settings'); empty:
    // every model the settings'.
    std::vector<float> model_damping;
    // Per model, its own deform_damping (1/s; negative: the solver settings'); empty: the settings'.
    std::vector<float> model_deform_damping;
    // Per model, its own PBD stretch stiffness per frame (negative: the solver settings'); empty:
    // every model the settings'.
    std::vector<float> model_stretch_stiffness;
    // The connected component each particle was in when the body was built (a particle a
    // topology edit adds takes its source's): the two sides of a cut are one part.
    std::vector<uint32_t> part_of_particle;
    // (inner part, outer part), sorted: a part that lay wholly inside another closed part when the
    // body was built (a stone in a fruit; sim/enclosure.h). Contact keeps it inside.
    std::vector<std::pair<uint32_t, uint32_t>> enclosed_parts;
};

// Where the body is: what the solver writes every step.
template <class Real>
struct BodyStateT {
    ParticlesT<Real> particles;
    std::vector<Real> distance_lambda;  // XPBD multipliers, one per distance constraint
    SleepState sleep;                   // which pieces rest, held (sim/sleep.h)
};

// What is derived from the structure and the state: rebuilt with the derived data (after every
// cut), kept current by the solver (the normals after each step, the fits' warm start).
template <class Real>
struct BodyCachesT {
    std::vector<Vec3f> normals;  // per particle, from the positions after each step
    VertexRings rings;           // per-vertex triangle rings of `triangles`, for normals
    std::vector<ShapeCluster> shapes;  // shape matching's clusters: rest offsets, weights, last rotation
};

template <class Real>
struct SoftBodyT : BodyStructureT<Real>, BodyStateT<Real>, BodyCachesT<Real> {
    size_t particle_count() const { return this->particles.size(); }
    // How many models the particles were loaded from (a scene's [model] and [[bodies]]); 1 where
    // the body does not say.
    size_t model_count() const {
        const std::vector<uint32_t>& m = this->model_of_particle;
        return m.empty() || m.size() != particle_count() ? 1 : size_t(*std::max_element(m.begin(), m.end())) + 1;
    }
    // The model of each piece (a piece never spans two: models share no triangle); all 0 where
    // the body does not say.
    std::vector<uint32_t> model_of_pieces() const {
        std::vector<uint32_t> out(this->pieces, 0);
        if (this->model_of_particle.size() != particle_count()) return out;
        for (size_t i = 0; i < particle_count(); ++i)
            if (this->piece_of_particle[i] < this->pieces) out[this->piece_of_particle[i]] = this->model_of_particle[i];
        return out;
    }
    // Current volume of a volume constraint (caps included), over the whole body's triangles.
    double volume(size_t constraint) const {
        const VolumeConstraint& c = this->volumes[constraint];
        return (triangles_six_volume<Real>(this->triangles, this->piece_of_particle, c.piece, this->particles.x) +
                caps_six_volume<Real>(c.cap_loops, this->particles.x)) /
               6.0;
    }
    // Pins the particle (inverse mass 0); it then moves only if the scene moves it.
    void pin(uint32_t particle) { this->particles.w[particle] = Real(0); }
    // The particle with the largest (or smallest) `axis` coordinate; ties: lowest index.
    uint32_t extreme_particle(int axis, bool largest = true) const {
        uint32_t best = 0;
        for (uint32_t i = 1; i < this->particles.size(); ++i) {
            const Real a = this->particles.x[i][axis], b = this->particles.x[best][axis];
            if (largest ? a > b : a < b) best = i;
        }
        return best;
    }
};
using SoftBody = SoftBodyT<float>;
using BodyStructure = BodyStructureT<float>;
using BodyState = BodyStateT<float>;
using BodyCaches = BodyCachesT<float>;
constexpr uint32_t k_no_piece = UINT32_MAX;

// The slots of one volume pass: the constraints that project now (not those done leaking), in
// their order, and the slot of each piece.
struct VolumeSlots {
    std::vector<uint32_t> slot_of_piece;
    std::vector<VolumeConstraint*> constraints;
    std::vector<float> share;  // VolumeLayout::share's room
    // VolumeLayout::w_most and skin_density: set where the masses are known to be as they will
    // be for the projections (once a substep: it costs a division a particle).
    VolumeWeights weights;
    // Per piece, 1 where this substep's contact candidates bring it against another piece: the
    // volume pass does not take back such a piece's net impulse (VolumeSums::push). Pressed into
    // its neighbour, the correction drove it further in every projection, and the contact's answer
    // came back as volume error: Suzanne's two cut halves pressed together until their edges
    // stretched four times and they flew apart at 10 m/s.
    std::vector<uint8_t> pressed;
    // Per slot: its MassMoments, summed at most once a substep (at the first projection that
    // scales its moves); `moments_ready` is cleared with each substep.
    std::vector<MassMoments> moments;
    std::vector<uint8_t> moments_ready;
};
template <class Real>
VolumeLayout volume_layout(SoftBodyT<Real>& b, VolumeSlots& slots) {
    slots.slot_of_piece.assign(b.pieces, k_no_volume);
    slots.constraints.clear();
    for (VolumeConstraint& v : b.volumes) {
        if (v.piece >= b.pieces) continue;
        slots.slot_of_piece[v.piece] = uint32_t(slots.constraints.size());
        slots.constraints.push_back(&v);
    }
    VolumeLayout l{&b.rings.ring, b.piece_of_particle, slots.slot_of_piece, slots.constraints.size()};
    l.w_most = slots.weights.w_most, l.skin_density = slots.weights.skin_density;
    if (b.rings.rest_area.size() == b.particle_count()) {
        slots.share.resize(b.particle_count());
        l.rest_area = b.rings.rest_area, l.open_fan = b.rings.open_fan, l.share = slots.share;
    }
    return l;
}
// Projects every volume constraint once, in one thread (the solver's stage runs the same phases
// on its threads).
template <class Real>
void solve_volumes(SoftBodyT<Real>& b, Vec4ArrayT<Real>& scratch, bool xpbd, Real stiffness, Real inv_h2) {
    VolumeSlots slots;
    slots.weights = volume_weights<Real>(std::span<const Real>(b.particles.w), b.rings.rest_area);
    const VolumeLayout l = volume_layout(b, slots);
    solve_volumes<Real>(slots.constraints, l, b.particles, scratch, xpbd, stiffness, inv_h2);
}

// The pieces of `triangles` (connected through shared vertices), one label per particle
// (k_no_piece for a particle in no triangle); returns their count.
uint32_t label_pieces(std::span<const mesh::Triangle> triangles, size_t particle_count, std::vector<uint32_t>& piece_of_particle);
// How many triangles each piece of `piece_of_particle` holds (`pieces` entries).
std::vector<size_t> piece_triangle_counts(std::span<const mesh::Triangle> triangles, std::span<const uint32_t> piece_of_particle,
                                          size_t pieces);

// Builds the body. `mesh` must be repaired (manifold with boundary, outward); the mesh's vertex
// order may change (reorder), so the body's particles are the reference afterwards.
core::Result<SoftBody> make_soft_body(mesh::TriangleMesh mesh, const SoftBodyDesc& desc);

// Recomputes what the solver derives from the body's lists: the colour grouping of the distance
// constraints, the vertex rings of the triangles, the pieces (volume constraints follow their
// piece's new label), the XPBD multipliers. Call it after changing particles, triangles or constraints by hand.
template <class Real>
void rebuild_derived(SoftBodyT<Real>& body);

// Capacity for `fraction` more particles, triangles and constraints in every array a topology
// edit appends to, so an edit costs what it touches and not a copy of the body (a copied body
// has none). Returns whether anything had to grow. Topology edits call it when room runs low.
bool reserve_headroom(SoftBody& body, float fraction = 0.25f);

// Rebuilds only the shape-matching clusters (part of rebuild_derived): after pinning, which
// changes the masses the fit weighs particles by.
template <class Real>
void rebuild_shape_clusters(SoftBodyT<Real>& body);

// The same body in double precision (state converted, constraints shared).
SoftBodyT<double> to_double(const SoftBody& body);

} // namespace pbdsplat::sim
