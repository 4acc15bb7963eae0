#pragma once
// A crumpling skin kept from folding through its own neighbourhood. Contact leaves a particle's
// own surface within a few edges alone (at rest it lies on it: sim/contact.h), yet that is where
// a deflating balloon creases and lays one fold through the next (docs/BENCHMARKS.md, "Surfaces
// through each other"). There, nearness says nothing; passing through does. Each substep pairs
// every particle with the triangles of its rest neighbourhood (not its own fan, nor one it lay on
// at rest) that it was over when the substep began and lies near; each iteration keeps it on the
// side it was on then, at a fraction of the contact thickness. A particle at rest lies beside its neighbours'
// triangles, never over them, so a resting or smoothly bending surface is never pushed: only a
// fold closing on itself is.
#include <cstdint>
#include <span>
#include <vector>

#include "core/thread_pool.h"
#include "sim/contact.h"
#include "sim/fold_edges.h"
#include "sim/soft_body.h"

namespace pbdsplat::sim {

// The gap a fold keeps, over the mean rest edge: well under the splats' size (half an edge), so a
// crease shows no seam, and enough that a particle pushed to it does not cross back by rounding.
inline constexpr float k_fold_thickness = 0.1f;

template <class Real>
class FoldGuardT {
public:
    // After prediction: the pairs that may meet this substep. Nothing for stiff bodies (their
    // pieces keep their shape and never fold) or without contact.
    void find(const SoftBodyT<Real>& body, const ContactSettings& s, bool stiff_bodies);
    // One sweep over them (every iteration).
    void project(ParticlesT<Real>& p) const;
    // Threads for the scan (the caller's pool; null: the calling thread alone). The candidates
    // do not depend on it.
    void set_pool(core::ThreadPool* pool) { pool_ = pool, edges_.set_pool(pool); }

    // Rest-neighbourhood pairs known, and this substep's candidates among them.
    size_t pairs() const { return near_.size(); }
    size_t candidates() const { return active_.size(); }
    // Edge pairs known, and this substep's candidates among them (sim/fold_edges.h).
    size_t edge_pairs() const { return edges_.pairs(); }
    size_t edge_candidates() const { return edges_.candidates(); }
    // Every list made again from `body` at the scale of the last build (what the lists kept
    // through topology edits must equal).
    void rebuild(const SoftBodyT<Real>& body);
    // The triangles particle i is guarded against (as last built or updated).
    std::span<const uint32_t> neighbourhood(uint32_t i) const {
        return i + 1 < start_.size() ? std::span<const uint32_t>(near_.data() + start_[i], start_[i + 1] - start_[i]) : std::span<const uint32_t>();
    }

private:
    struct Candidate {
        uint32_t particle;
        uint32_t a, b, c;  // the triangle's corners
        float side;  // +1 in front of the triangle at the substep's start, -1 behind
    };
    bool stale(const SoftBodyT<Real>& body, const ContactSettings& s) const;
    void build(const SoftBodyT<Real>& body, const ContactSettings& s);
    // After a topology edit: the lists of the particles within the neighbourhood of a triangle it
    // changed or added made again, the rest kept. False where it cannot (the body shrank).
    bool update(const SoftBodyT<Real>& body);
    void build_edges(const SoftBodyT<Real>& body);
    void mark_around(const SoftBodyT<Real>& body, uint32_t t, std::vector<uint8_t>& redo);
    void gather(const SoftBodyT<Real>& body, uint32_t i, float radius, std::vector<uint32_t>& out);
    void frame_triangles(const SoftBodyT<Real>& body);
    void scan(const SoftBodyT<Real>& body, uint32_t first, uint32_t last, std::vector<Candidate>& out);
    core::ThreadPool* pool_ = nullptr;
    std::vector<std::vector<Candidate>> chunk_;  // the scan's candidates per chunk
    // Fewer particles than this a chunk cost more to hand out than they take to scan.
    static constexpr uint32_t k_particles_per_chunk = 256;

    // Per particle, the live triangles of its piece within the scale's exclusion radius of it at
    // rest, not its own (CSR: near_[start_[i] .. start_[i + 1]]); made when the body is first
    // seen, remade around each topology edit at that scale.
    std::vector<uint32_t> start_, near_;
    std::vector<mesh::Triangle> built_triangles_list_;  // the triangles they were made from
    std::vector<uint32_t> old_start_, old_near_;        // update's scratch
    size_t built_particles_ = 0, built_triangles_ = 0, built_pieces_ = 0;
    float settings_thickness_ = 0.0f;
    ContactScale scale_;  // the body's, as last built
    std::vector<uint32_t> vertex_stamp_, triangle_stamp_, queue_;  // build scratch
    // Per triangle this substep: its bounding sphere predicted (radius < 0: dead or degenerate),
    // apart from its planes (unit normal, offset) predicted and at the substep's start, since
    // most pairs need the sphere alone.
    struct TrianglePlanes {
        Vec4f plane, plane0;
    };
    struct TriangleBound {
        Vec4f sphere;  // centre, radius
        Vec4f normal;  // unit, predicted (w unused)
    };
    std::vector<TriangleBound> spheres_;
    // Per particle this substep: whether its neighbourhood bends back on itself (a triangle of it
    // turned more than a right angle from the particle's normal), where alone a fold can close.
    std::vector<uint8_t> folded_;
    std::vector<TrianglePlanes> planes_;
    float on_ = 0.0f;         // within this of a triangle at rest, a particle lies on it
    float thickness_ = 0.0f;  // kept between a fold's layers
    std::vector<Candidate> active_;
    FoldEdgesT<Real> edges_;  // the same neighbourhoods' edges against each other
    bool edges_wanted_ = false;
};
using FoldGuard = FoldGuardT<float>;

} // namespace pbdsplat::sim
