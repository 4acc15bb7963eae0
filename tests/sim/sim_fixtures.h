#pragma once
// Small bodies and a frame loop shared by the sim suites.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "mesh/procedural.h"
#include "sim/solver.h"
#include "topology/cut.h"
#include "support/why.h"

namespace pbdsplat::test {

inline sim::SoftBody make_body(mesh::TriangleMesh m, sim::SoftBodyDesc desc = {}) {
    auto b = sim::make_soft_body(std::move(m), desc);
    REQUIRE_MESSAGE(b.ok(), test::why(b));
    return std::move(b).value();
}

// Cuts `b` by the plane through `point` with normal `normal` (need not be unit length) into two
// pieces, or fails the test.
inline void cut_in_two(sim::SoftBody& b, const Vec3f& point, const Vec3f& normal, const topology::CutOptions& options = {}) {
    auto plane = topology::plane_cut(point, normal);
    REQUIRE(plane.ok());
    auto change = topology::cut(b, plane.value(), options);
    REQUIRE_MESSAGE(change.ok(), test::why(change));
    REQUIRE(b.pieces == 2);
}

inline Eigen::Affine3f moved_by(const Vec3f& t) {
    Eigen::Affine3f a = Eigen::Affine3f::Identity();
    a.translate(t);
    return a;
}

// Moves every particle of `piece` by t (the rest shape stays where it was).
inline void move_piece(sim::SoftBody& b, uint32_t piece, const Vec3f& t) {
    for (size_t i = 0; i < b.particle_count(); ++i)
        if (b.piece_of_particle[i] == piece) b.particles.x[i] += sim::to4(t);
}

// Two 1 m boxes as two pieces, the second centred at `second` at rest.
inline sim::SoftBody two_boxes_at_rest(const Vec3f& second) {
    mesh::TriangleMesh m = mesh::box(Vec3f(1.0f, 1.0f, 1.0f), 2);
    mesh::append(m, mesh::box(Vec3f(1.0f, 1.0f, 1.0f), 2), moved_by(second));
    sim::SoftBody b = make_body(std::move(m));
    REQUIRE(b.pieces == 2);
    return b;
}

// The lowest and highest y of a piece's particles.
inline float lowest_y(const sim::SoftBody& b, uint32_t piece) {
    float y = INFINITY;
    for (size_t i = 0; i < b.particle_count(); ++i)
        if (b.piece_of_particle[i] == piece) y = std::min(y, b.particles.x[i].y());
    return y;
}
inline float highest_y(const sim::SoftBody& b, uint32_t piece) {
    float y = -INFINITY;
    for (size_t i = 0; i < b.particle_count(); ++i)
        if (b.piece_of_particle[i] == piece) y = std::max(y, b.particles.x[i].y());
    return y;
}

inline double total_mass(const sim::SoftBody& b) {
    double m = 0.0;
    for (float w : b.particles.w) m += w > 0.0f ? 1.0 / double(w) : 0.0;
    return m;
}

inline bool all_finite(const sim::SoftBody& b) {
    for (size_t i = 0; i < b.particle_count(); ++i)
        if (!b.particles.x[i].allFinite() || !b.particles.v[i].allFinite()) return false;
    return true;
}

inline void run(sim::SoftBody& b, int frames, float dt, const sim::SolverSettings& s, const sim::Colliders& c = {}) {
    sim::Solver solver;
    for (int f = 0; f < frames; ++f) solver.step(b, dt, s, c, sim::DragConstraint{});
}

} // namespace pbdsplat::test
