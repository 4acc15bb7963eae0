#include <doctest/doctest.h>

#include "mesh/procedural.h"
#include "mesh/topology.h"
#include "sim/solver.h"
#include "topology/separate.h"

using namespace pbdsplat;

namespace {
sim::SoftBody sphere() {
    auto b = sim::make_soft_body(mesh::icosphere(3), {});
    REQUIRE(b.ok());
    return std::move(b).value();
}
double total_mass(const sim::SoftBody& b) {
    double m = 0.0;
    for (float w : b.particles.w) m += w > 0.0f ? 1.0 / double(w) : 0.0;
    return m;
}
bool above(const sim::SoftBody& b, uint32_t t) {
    const auto& tri = b.triangles[t];
    return (b.particles.x[tri[0]] + b.particles.x[tri[1]] + b.particles.x[tri[2]]).x() >= 0.0f;
}
} // namespace

TEST_SUITE("topology/separate") {
    TEST_CASE("a plane through a sphere separates it into two pieces, keeping mass and invariants") {
        sim::SoftBody b = sphere();
        const size_t n = b.particle_count();
        const double mass = total_mass(b);
        auto change = topology::separate(b, [&](uint32_t t) { return above(b, t); }, [](uint32_t) { return true; });
        REQUIRE(change.ok());
        CHECK(change->components_before == 1);
        CHECK(change->components_after == 2);
        CHECK(change->split_vertices > 10);
        CHECK(b.particle_count() == n + change->split_vertices);
        CHECK(total_mass(b) == doctest::Approx(mass).epsilon(1e-5));
        CHECK(topology::check_invariants(b).ok());
        CHECK(b.volumes.size() == 2);  // each half keeps a (capped) volume of its own
        for (const auto& v : b.volumes) CHECK(v.cap_loops.size() == 1);
        // The halves move apart freely: simulate and check nothing blows up.
        sim::SolverSettings s;
        sim::Solver solver;
        for (int f = 0; f < 60; ++f) solver.step(b, 1.0f / 60.0f, s, {}, {});
        for (const auto& x : b.particles.x) CHECK(x.allFinite());
    }

    TEST_CASE("a cut that may not split every vertex stops inside the surface") {
        sim::SoftBody b = sphere();
        // Only vertices with y > 0 may be split: the cut opens the top half and stops there.
        auto change = topology::separate(
            b, [&](uint32_t t) { return above(b, t); }, [&](uint32_t v) { return b.particles.x[v].y() > 0.0f; });
        REQUIRE(change.ok());
        CHECK(change->components_after == 1);  // still one piece, with a slit
        CHECK(change->split_vertices > 0);
        CHECK(topology::check_invariants(b).ok());
        CHECK(mesh::boundary_loops(mesh::TriangleMesh{b.rest_positions, b.triangles, {}, {}, {}}).size() == 1);
    }

    TEST_CASE("invariant checks catch broken bodies") {
        sim::SoftBody b = sphere();
        b.distance.push_back({0, uint32_t(b.particle_count() + 5), 1.0f, 0.0f});
        CHECK_FALSE(topology::check_invariants(b).ok());
        b = sphere();
        std::swap(b.triangles[0][1], b.triangles[0][2]);
        CHECK(topology::check_invariants(b).error().message.find("orientation") != std::string::npos);
    }
}
