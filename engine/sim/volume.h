#pragma once
// The global volume (overpressure) constraints, paper eqs. 7 and 9.
//
// All of a body's volume constraints project in one pass, in phases threads can share: gather
// the gradient per particle in fixed blocks of particles (each block with its partial sums per
// constraint), add the virtual caps, reduce the sums block by block in order, then move every
// particle. Pieces share no particle, so projecting them together is projecting them one after
// another; fixed blocks make the result the same for any thread count.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <span>
#include <utility>
#include <vector>

#include "mesh/triangle_mesh.h"
#include "sim/constraints.h"
#include "sim/particles.h"
#include "sim/slack_lists.h"
#include "sim/vec4_ops.h"

namespace pbdsplat::sim {

constexpr size_t k_volume_block = 1024;  // particles per partial sum
constexpr uint32_t k_no_volume = UINT32_MAX;

// What the volume pass reads besides the particles: the body's vertex rings and which
// constraint (slot) projects each piece.
struct VolumeLayout {
    const SlackLists<std::array<uint32_t, 2>>* ring = nullptr;  // (j, k) of each triangle (i, j, k) at i
    std::span<const uint32_t> piece_of_particle;
    std::span<const uint32_t> slot_of_piece;  // k_no_volume: the piece is not projected
    size_t slots = 0;
    // VertexRings::rest_area per particle, and room for each particle's push_share (both empty:
    // every particle moves along all of its gradient).
    std::span<const float> rest_area;
    std::span<const uint8_t> open_fan;  // VertexRings::open_fan, beside rest_area
    std::span<float> share;
    float share_of(uint32_t i) const { return share.empty() ? 1.0f : share[i]; }
    // The inverse mass the pass moves a particle by: at most k_volume_lightest times the mean
    // mass's inverse (volume_weights).
    float w_most = INFINITY;
    // The skin's mass per area (VolumeWeights::skin_density): what a virtual cap weighs.
    float skin_density = 0.0f;
    template <class Real>
    Real weight(Real w) const { return std::min(w, Real(w_most)); }
    uint32_t slot_of(uint32_t i) const {
        const uint32_t p = piece_of_particle[i];
        return p < slot_of_piece.size() ? slot_of_piece[p] : k_no_volume;
    }
};

// How much of its gradient a particle is moved along: all of it, unless its fan of triangles
// (twice their vector area, whose length is the gradient's at rest) has grown to more than
// k_push_growth times its rest length, and then only that much. The projection's step spreads
// the volume's error in proportion to w |g|^2 (eq. 9), so a region stretched far beyond its
// neighbours takes ever more of it and grows faster still: a balloon with next to no stretch
// stiffness grew spikes metres long within a second. A body inflating evenly is held everywhere
// alike, which the step size undoes. The fan, not the gradient, is measured: a particle on a cut
// also carries the virtual cap's term, which is as large as the cap is wide, not a stretch.
inline constexpr float k_push_growth = 4.0f;
template <class Real>
float push_share(float rest_area, const Vec4<Real>& fan) {
    const Real most = Real(k_push_growth * rest_area), f2 = fan.squaredNorm();
    return f2 > most * most ? float(most / std::sqrt(f2)) : 1.0f;
}

// Eq. 9 moves particle i by s w_i g_i: a particle far lighter than its neighbours takes as many
// times their share of the error. A model's slivers make such particles (the decimated Stanford
// bunny's base holes are rimmed by vertices of 1/100 of the mean mass, the loader's floor), and a
// pressure factor of 100 set at once shot them out as spikes 150 of their edges long in one step.
// In the volume pass a particle weighs at least a quarter of the mean: the move it is owed, at
// most four times its neighbours'. Elsewhere (edges, contact, shape) it keeps its own mass.
inline constexpr float k_volume_lightest = 4.0f;
// The cap of one of the model's own holes is skin the model lacks, and it pushes its rim as skin
// would (its triangles' terms of the gradient), so it weighs as skin would too: each rim particle
// carries the mass of its two cap triangles' thirds and its 1/n of the centre's third, at the
// skin's mean density (over the cap's present area: a hole stretched open weighs more, which holds
// it as push_share holds a stretched fan). Weighing only its own fans, a rim took the whole cap's
// push: a vase blown to twice its volume had its mouth drawn up into a jagged crown, the teapot's
// lid rose as a torn tower, and the Stanford bunny's base holes (rims of slivers, 1/100 to 1/5 of
// the mean mass) grew spikes at a pressure factor of 3.
struct VolumeWeights {
    float w_most = INFINITY;    // k_volume_lightest over the mean mass; INFINITY for none that moves
    float skin_density = 0.0f;  // the moving particles' mass over their fans' area (0: none)
};
// Over the particles that move (w > 0); rest_area as VertexRings::rest_area (twice each fan's
// vector area, so six times the surface's area in all where it is flat), or empty.
template <class Real>
VolumeWeights volume_weights(std::span<const Real> w, std::span<const float> rest_area);

struct VolumeSums {
    double eighteen_v = 0.0;  // sum of x_i . g_i = 18 V (Euler, V homogeneous of degree 3)
    double denom = 0.0;       // sum of w_i s_i |g_i|^2, g = gradient of 6V, s = push_share
    // Eq. 9 gives particle i the impulse s g_i, and the g_i of a closed surface sum to 0: the
    // pass moves no centre of mass. Where push_share or the weight cap scale a particle's move by
    // f_i = weight(w_i) s_i / w_i, the impulses sum to s * push (exactly 0 where nothing is
    // scaled), and a balloon blown up at once shot itself off (a Suzanne at 23 m/s). Their
    // moments about the origin likewise sum to s * turn (the g_i have none: a turned body has the
    // same volume), and the bunny blown up at once tumbled and rolled out of the frame.
    // volume_nudge takes both back by moving the piece rigidly, which changes no volume.
    Vec3d push = Vec3d::Zero();  // sum (f_i - 1) g_i
    Vec3d turn = Vec3d::Zero();  // sum (f_i - 1) x_i x g_i
    void add(const VolumeSums& o) { eighteen_v += o.eighteen_v, denom += o.denom, push += o.push, turn += o.turn; }
    bool unbalanced() const { return !push.isZero(0.0) || !turn.isZero(0.0); }
};
// A piece's mass and its first and second moments over the particles that move: its centre and
// inertia for volume_nudge. Summed once a substep, and only for pieces whose moves are scaled:
// summed in the gather, they cost a hanging icosphere:6 a sixth more Stage A for nothing.
struct MassMoments {
    double mass = 0.0;                                 // sum of m_i = 1 / w_i
    Vec3d first = Vec3d::Zero();                       // sum m_i x_i
    Eigen::Matrix3d second = Eigen::Matrix3d::Zero();  // sum m_i x_i x_i^T
    void add(const MassMoments& o) { mass += o.mass, first += o.first, second += o.second; }
};
// One block's partial sums: a block of neighbouring particles meets few pieces, so it keeps
// (slot, sums) for those it met, in the order met, instead of an entry for every slot (a body
// cut into thousands of pieces would clear thousands per block).
using BlockSums = std::vector<std::pair<uint32_t, VolumeSums>>;

// 6V of the triangles labelled `piece` (their first corner's label), in double precision.
template <class Real>
double triangles_six_volume(std::span<const mesh::Triangle> triangles, std::span<const uint32_t> piece_of_particle, uint32_t piece,
                            const Vec4ArrayT<Real>& x);
// 6V of the virtual fan closing one loop at its centroid, and of several.
template <class Real>
double cap_six_volume(std::span<const uint32_t> loop, const Vec4ArrayT<Real>& x);
template <class Real>
double caps_six_volume(const std::vector<std::vector<uint32_t>>& loops, const Vec4ArrayT<Real>& x);

// The area a closed loop spans (half its vector area's length): 0 for a slit whose two sides lie
// on each other. `position(i)` gives particle i's place as a Vec3d.
template <class Position>
double loop_area(std::span<const uint32_t> loop, const Position& position) {
    Vec3d a = Vec3d::Zero();
    for (size_t k = 0; k < loop.size(); ++k) a += position(loop[k]).cross(position(loop[(k + 1) % loop.size()]));
    return 0.5 * a.norm();
}

// How fast a leaking constraint's gas escapes now (1/s): VolumeConstraint::leak once its openings'
// area (the vector areas of its loops that are not the model's own sealed holes) reaches
// k_open_area of its rest volume to the power 2/3 (a hole about a fifth of a ball's radius
// across), in proportion below that. 0 for a sealed constraint.
template <class Real>
float leak_rate(const VolumeConstraint& c, const Vec4ArrayT<Real>& x);
inline constexpr double k_open_area = 0.05;

size_t volume_blocks(size_t particles);
// Gradient of 6V at the particles of block `b` that a slot projects, into grad, and their
// push_share into l.share; their partial sums into `sums` (cleared first).
template <class Real>
void volume_gather(const VolumeLayout& l, const ParticlesT<Real>& p, Vec4ArrayT<Real>& grad, size_t b, BlockSums& sums);
// Per-block partial sums, as (slot, sums) pairs, added per slot block by block in order (the
// same for any thread count). Sums: VolumeSums or MassMoments.
template <class Sums>
void reduce_blocks(std::span<const std::vector<std::pair<uint32_t, Sums>>> blocks, std::span<Sums> totals) {
    std::fill(totals.begin(), totals.end(), Sums{});
    for (const auto& block : blocks)
        for (const auto& [slot, sums] : block) totals[slot].add(sums);
}
// Adds the virtual caps' terms of one constraint (serial: they are few) to grad, and to `sums`
// what they change in that constraint's sums.
template <class Real>
void volume_caps(const VolumeLayout& l, const VolumeConstraint& c, const ParticlesT<Real>& p, Vec4ArrayT<Real>& grad, VolumeSums& sums);
// The mass moments of the slots marked in `wanted` over the particles of block b, as
// (slot, moments) in the order met; added per slot by reduce_blocks.
using BlockMoments = std::vector<std::pair<uint32_t, MassMoments>>;
template <class Real>
void volume_moments(const VolumeLayout& l, const ParticlesT<Real>& p, std::span<const uint8_t> wanted, size_t b, BlockMoments& out);
// The step size along the gradient; updates c.lambda in XPBD mode. 0 when nothing can move.
// The error it answers is held to k_volume_reach of the present volume.
inline constexpr double k_volume_reach = 0.5;
template <class Real>
Real volume_step(VolumeConstraint& c, const VolumeSums& total, bool xpbd, Real stiffness, Real alpha_tilde);
// A rigid move of a piece: x += shift + turn x (x - centre), turn a small angle.
template <class Real>
struct RigidNudge {
    Vec4<Real> shift = Vec4<Real>::Zero(), turn = Vec4<Real>::Zero(), centre = Vec4<Real>::Zero();
    bool moves = false;  // most pieces' moves are not scaled: no cross product a particle for them
    Vec4<Real> at(const Vec4<Real>& x) const { return moves ? Vec4<Real>(shift + cross3<Real>(turn, x - centre)) : Vec4<Real>::Zero(); }
};
// The rigid move that cancels a slot's net impulse and its moment about the centre of mass for a
// step `step` (VolumeSums::push, turn): none where nothing was scaled. The turn is left out for a
// piece with no inertia to speak of in some direction (a particle, a line).
template <class Real>
RigidNudge<Real> volume_nudge(const VolumeSums& total, const MassMoments& m, Real step);
// x_i += steps[slot] * w_i * s_i * g_i + nudges[slot].at(x_i) for the projected particles of
// block b that move.
template <class Real>
void volume_apply(const VolumeLayout& l, ParticlesT<Real>& p, const Vec4ArrayT<Real>& grad, std::span<const Real> steps,
                  std::span<const RigidNudge<Real>> nudges, size_t b);

// All phases in one thread for the constraints `slot_constraints` (slot order). `scratch`
// holds one gradient per particle.
template <class Real>
void solve_volumes(std::span<VolumeConstraint* const> slot_constraints, const VolumeLayout& l, ParticlesT<Real>& p,
                   Vec4ArrayT<Real>& scratch, bool xpbd, Real stiffness, Real inv_h2);

} // namespace pbdsplat::sim
