#include <doctest/doctest.h>

#include <cmath>

#include "mesh/procedural.h"
#include "mesh/topology.h"

using namespace pbdsplat;

TEST_SUITE("mesh/procedural") {
    TEST_CASE("icosphere counts follow V = 10*4^L + 2, F = 20*4^L") {
        for (uint32_t level = 0; level <= 5; ++level) {
            const auto m = mesh::icosphere(level);
            const size_t f = 20u * (1u << (2 * level));
            CHECK(m.triangle_count() == f);
            CHECK(m.vertex_count() == f / 2 + 2);
        }
    }

    TEST_CASE("icosphere is closed, consistently outward and on the sphere") {
        for (uint32_t level : {0u, 2u, 4u}) {
            const auto m = mesh::icosphere(level, 2.5f);
            CHECK(mesh::boundary_edge_count(m) == 0);
            CHECK(mesh::is_closed_and_oriented(m));
            for (const Vec3f& p : m.positions) CHECK(p.norm() == doctest::Approx(2.5f).epsilon(1e-6));
            // Outward orientation: positive volume, approaching the sphere's from below.
            const double v = mesh::signed_volume(m), sphere = 4.0 / 3.0 * M_PI * 2.5 * 2.5 * 2.5;
            CHECK(v > 0.0);
            CHECK(v < sphere);
            if (level == 4) CHECK(v / sphere > 0.99);  // level 4: 0.998 of the sphere
        }
    }

    TEST_CASE("the table is five closed parts that touch without sharing a vertex, in square cells") {
        const auto m = mesh::table(2);
        CHECK(mesh::is_closed_and_oriented(m));
        std::vector<uint32_t> part;
        REQUIRE(mesh::vertex_components(m.triangles, m.positions.size(), part) == 5);
        // Top 1.2 x 0.05 x 0.8 and four legs 0.05 x (0.7 - a hair) x 0.05.
        const double legs = 4.0 * 0.05 * 0.05 * (0.7 - 0.02 * 0.025);
        CHECK(mesh::signed_volume(m) == doctest::Approx(1.2 * 0.05 * 0.8 + legs).epsilon(1e-4));
        const mesh::Bounds b = mesh::bounds(m);
        CHECK(b.min.y() == doctest::Approx(-0.375f));
        CHECK(b.max.y() == doctest::Approx(0.375f));
        // Square cells: no edge longer than a cell's diagonal (0.025 * sqrt 2).
        for (const auto& t : m.triangles)
            for (int k = 0; k < 3; ++k) CHECK((m.positions[t[k]] - m.positions[t[(k + 1) % 3]]).norm() < 0.0355f);  // measured: 0.0354 at most
    }

    TEST_CASE("flipping one triangle breaks the orientation check") {
        auto m = mesh::icosphere(1);
        std::swap(m.triangles[3][1], m.triangles[3][2]);
        CHECK_FALSE(mesh::is_closed_and_oriented(m));
        m.triangles.pop_back();
        CHECK(mesh::boundary_edge_count(m) == 3);
    }

    TEST_CASE("vertex normals of a sphere point outward") {
        const auto m = mesh::icosphere(3);
        const auto n = mesh::vertex_normals(m);
        for (size_t i = 0; i < m.vertex_count(); ++i) CHECK(n[i].dot(m.positions[i]) > 0.99f);  // a vertex normal of a sphere is radial, to a few degrees
    }

    TEST_CASE("mean edge length halves with each subdivision") {
        const float e3 = mesh::mean_edge_length(mesh::icosphere(3)), e4 = mesh::mean_edge_length(mesh::icosphere(4));
        CHECK(e4 / e3 == doctest::Approx(0.5f).epsilon(0.03));
    }

    TEST_CASE("fibonacci sphere points lie on the sphere and spread out") {
        const auto p = mesh::fibonacci_sphere(1000, 2.0f);
        REQUIRE(p.size() == 1000);
        Vec3f mean = Vec3f::Zero();
        for (const Vec3f& q : p) {
            CHECK(q.norm() == doctest::Approx(2.0f).epsilon(1e-5));
            mean += q / 1000.0f;
        }
        CHECK(mean.norm() < 0.01f);  // 1000 points uniform on a sphere: their mean within 0.5 %
    }
}
