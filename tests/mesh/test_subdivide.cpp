#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "mesh/procedural.h"
#include "mesh/subdivide.h"

using namespace pbdsplat;

namespace {

float longest_edge(const mesh::TriangleMesh& m, size_t first_triangle, size_t last_triangle) {
    float most = 0.0f;
    for (size_t t = first_triangle; t < last_triangle; ++t)
        for (int k = 0; k < 3; ++k)
            most = std::max(most, (m.positions[m.triangles[t][k]] - m.positions[m.triangles[t][(k + 1) % 3]]).norm());
    return most;
}

} // namespace

TEST_SUITE("mesh/subdivide") {
    TEST_CASE("a low-poly part beside a fine one is subdivided flat; the fine one is left as it was") {
        mesh::TriangleMesh m = mesh::icosphere(3);  // longest edge 0.17 of its diagonal
        const size_t sphere_vertices = m.vertex_count(), sphere_triangles = m.triangle_count();
        const mesh::TriangleMesh sphere = m;
        mesh::append(m, mesh::box(Vec3f(1.0f, 1.0f, 1.0f), 1), Eigen::Affine3f(Eigen::Translation3f(3.0f, 0.0f, 0.0f)));
        REQUIRE(m.vertex_count() == sphere_vertices + 8);
        const double volume = mesh::signed_volume(m);

        // The box's longest edge (a face's diagonal) is 0.82 of its own diagonal: halved twice,
        // 0.20, under 0.35.
        CHECK(mesh::refine_coarse_parts(m, 0.35f, 4, 100000) == 2);
        CHECK(m.triangle_count() == sphere_triangles + 12 * 16);
        CHECK(m.vertex_count() == sphere_vertices + 98);  // 6 faces of 5 x 5 points, shared along their rims
        CHECK(mesh::is_closed_and_oriented(m));
        CHECK(mesh::signed_volume(m) == doctest::Approx(volume).epsilon(1e-6));  // flat: still a box
        for (size_t i = 0; i < sphere_vertices; ++i) CHECK(m.positions[i] == sphere.positions[i]);
        size_t sphere_kept = 0;
        for (const mesh::Triangle& t : m.triangles) sphere_kept += t[0] < sphere_vertices && t[1] < sphere_vertices && t[2] < sphere_vertices;
        CHECK(sphere_kept == sphere_triangles);
        // The box's reach is 0.35 of its diagonal (sqrt 3): 0.61; its longest edge now a face's
        // diagonal over 4, 0.354 (the ball's, about 0.2, as before).
        CHECK(longest_edge(m, 0, m.triangle_count()) <= 0.35f * std::sqrt(3.0f));
    }

    TEST_CASE("refining parts stays within the triangle budget, and a fine mesh is not touched") {
        mesh::TriangleMesh boxes;
        for (int k = 0; k < 10; ++k)
            mesh::append(boxes, mesh::box(Vec3f(1.0f, 1.0f, 1.0f), 1), Eigen::Affine3f(Eigen::Translation3f(2.0f * float(k), 0.0f, 0.0f)));
        mesh::TriangleMesh within = boxes;
        // Two levels would make 1,920 triangles; one level's 480 fits under 1,000.
        CHECK(mesh::refine_coarse_parts(within, 0.35f, 4, 1000) == 1);
        CHECK(within.triangle_count() == 480);
        CHECK(mesh::is_closed_and_oriented(within));

        mesh::TriangleMesh fine = mesh::icosphere(2);
        const size_t before = fine.triangle_count();
        CHECK(mesh::refine_coarse_parts(fine, 0.35f, 4, 100000) == 0);
        CHECK(fine.triangle_count() == before);
    }
}
