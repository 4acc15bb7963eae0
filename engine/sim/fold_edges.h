#pragma once
// A fold's edges kept from slicing through each other. The fold guard (sim/fold_guard.h) keeps a
// particle on its side of the triangles it is over, yet two layers of a crease still cross where
// an edge of one passes through an edge of the other with neither edge's corners over the other's
// triangles: the ridge of one fold laid across the next. Each substep pairs the edges of a
// particle's rest neighbourhood whose closest points lay inside both edges when the substep began
// and lie near; each iteration keeps the two on the side they were on then, along the normal of
// both, at the fold guard's gap. Two edges of a surface that is not folded over itself never
// overlap seen along that normal (their lines meet outside one of them), so they are never paired.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "core/thread_pool.h"
#include "sim/particles.h"
#include "sim/soft_body.h"

namespace pbdsplat::sim {

// Closest points of the lines through segments (p0, p1) and (q0, q1), as the parameters along
// each (0 and 1: the ends); false where the lines are parallel within `sin_min`.
bool line_closest_params(const Vec3f& p0, const Vec3f& p1, const Vec3f& q0, const Vec3f& q1, float sin_min, float& s, float& t);

template <class Real>
class FoldEdgesT {
public:
    // The edge pairs of each particle's neighbourhood (`start`/`near`: per particle, the
    // triangles the fold guard holds it against, CSR), those whose rest distance lies between
    // `on` (one surface at rest: a slit's two sides) and `radius`.
    void build(const SoftBodyT<Real>& body, std::span<const uint32_t> start, std::span<const uint32_t> near, float radius, float on);
    // Nothing known (made again by the next build).
    void reset() { edges_.clear(), runs_.clear(), pairs_.clear(), active_.clear(), built_ = false; }
    bool built() const { return built_; }
    // After prediction: the pairs that may cross this substep.
    // Only the edges with a corner whose neighbourhood is `folded` (per particle) can cross.
    void find(const SoftBodyT<Real>& body, std::span<const uint8_t> folded, float thickness, float reach);
    // One sweep over them (every iteration).
    void project(ParticlesT<Real>& p) const;
    void clear_candidates() { active_.clear(); }
    // Threads for the scan (null: the calling thread alone); the candidates do not depend on it.
    void set_pool(core::ThreadPool* pool) { pool_ = pool; }

    size_t pairs() const { return pairs_.size(); }
    size_t candidates() const { return active_.size(); }

private:
    struct Candidate {
        uint32_t a, b, c, d;  // edge ab against edge cd
        Vec3f n0;             // their normal at the substep's start, from ab towards cd
    };
    void make_edges(const SoftBodyT<Real>& body);
    void test(const ParticlesT<Real>& p, uint32_t a, uint32_t b, const Vec4f& se, uint32_t f, std::vector<Candidate>& out) const;
    void scan(const ParticlesT<Real>& p, std::span<const uint8_t> folded, size_t first, size_t last, std::vector<Candidate>& out) const;
    core::ThreadPool* pool_ = nullptr;
    std::vector<std::vector<Candidate>> chunk_;  // the scan's candidates per chunk
    static constexpr size_t k_edges_per_chunk = 512;
    std::vector<std::array<uint32_t, 2>> edges_;
    std::vector<std::array<uint32_t, 3>> triangle_edges_;  // per triangle (UINT32_MAX: dead)
    // Each pair once: per edge, the edges it is held against (pairs_[begin .. end]).
    struct Run {
        uint32_t edge, begin, end;
    };
    std::vector<Run> runs_;
    std::vector<uint32_t> pairs_;
    std::vector<uint32_t> stamp_;                           // build scratch, per edge
    std::vector<Vec4f> spheres_;                            // per edge, predicted
    std::vector<Candidate> active_;
    float thickness_ = 0.0f, reach_ = 0.0f;
    bool built_ = false;
};
using FoldEdges = FoldEdgesT<float>;

} // namespace pbdsplat::sim
