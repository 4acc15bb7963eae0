#include <doctest/doctest.h>

#include <algorithm>
#include <random>
#include <set>

#include "mesh/closest_point.h"
#include "mesh/decimate.h"
#include "asset/mesh_spec.h"
#include "asset/model_path.h"
#include "mesh/procedural.h"
#include "support/skip.h"
#include "support/why.h"

using namespace pbdsplat;

namespace {
// The largest distance from a vertex of `from` to the surface `to`, over the diagonal: one
// side of the Hausdorff distance, sampled at the vertices.
float vertex_distance(const mesh::TriangleMesh& from, const mesh::TriangleMesh& to) {
    const mesh::TriangleGrid grid(to.positions, to.triangles);
    float worst = 0.0f;
    for (const Vec3f& p : from.positions) worst = std::max(worst, grid.distance(p));
    return worst / mesh::bounds(to).diagonal();
}
} // namespace

TEST_SUITE("mesh/decimate") {
    TEST_CASE("closest point on a triangle agrees with a dense search") {
        std::mt19937 rng(3);
        std::uniform_real_distribution<float> u(-1.5f, 1.5f);
        const Vec3f a(0, 0, 0), b(1, 0, 0.2f), c(0.3f, 0.9f, -0.1f);
        for (int k = 0; k < 200; ++k) {
            const Vec3f p(u(rng), u(rng), u(rng));
            const Vec2f w = mesh::closest_point_barycentric(p, a, b, c);
            const float d = (a + w.x() * (b - a) + w.y() * (c - a) - p).norm();
            float best = 1e9f;
            for (int i = 0; i <= 200; ++i)
                for (int j = 0; i + j <= 200; ++j) best = std::min(best, (a + (float(i) / 200.0f) * (b - a) + (float(j) / 200.0f) * (c - a) - p).norm());
            CHECK(d <= best + 1e-5f);
            CHECK(d >= best - 0.02f);
        }
    }

    TEST_CASE("a closed sphere stays closed, manifold and near the original") {
        const mesh::TriangleMesh fine = mesh::icosphere(5);  // 10,242 vertices
        auto d = mesh::decimate(fine, {1000, true}, "icosphere:5");
        REQUIRE(d.ok());
        const mesh::TriangleMesh& c = d.value().mesh;
        CHECK(mesh::is_closed_and_oriented(c));
        CHECK(c.vertex_count() >= 750);
        CHECK(c.vertex_count() <= 1250);
        CHECK(mesh::signed_volume(c) > 0.0);
        // Both sides of the distance, sampled at the vertices: within 1 % of the diagonal.
        CHECK(vertex_distance(fine, c) < 0.01f);
        CHECK(vertex_distance(c, fine) < 1e-6f);  // the coarse vertices are the model's own
    }

    TEST_CASE("a target at or above the vertex count keeps the mesh; below 4 is an error") {
        const mesh::TriangleMesh fine = mesh::icosphere(2);
        auto same = mesh::decimate(fine, {100000, true}, "icosphere:2");
        REQUIRE(same.ok());
        CHECK(same.value().mesh.vertex_count() == fine.vertex_count());
        auto bad = mesh::decimate(fine, {3, true}, "icosphere:2");
        REQUIRE(!bad.ok());
        CHECK(bad.error().to_string().find("at least 4") != std::string::npos);
    }

    TEST_CASE("a mesh with fewer than two triangles per vertex decimates instead of aborting") {
        // An open 10 x 10 sheet: 121 vertices, 200 triangles. Asking for 110 vertices at two
        // triangles each asked the simplifier for more triangles than there are (it asserted).
        const mesh::TriangleMesh sheet = mesh::grid_sheet(10, 2.0f);
        REQUIRE(sheet.vertex_count() == 121);
        for (uint32_t target : {60u, 110u, 120u}) {
            CAPTURE(target);
            auto d = mesh::decimate(sheet, {target, false}, "sheet");
            REQUIRE_MESSAGE(d.ok(), test::why(d));
            CHECK(d.value().mesh.vertex_count() <= sheet.vertex_count());
            CHECK(d.value().mesh.triangle_count() >= 4);
        }
    }

    TEST_CASE("the bunny decimates to an oriented manifold with its scan holes kept") {
        if (!asset::find_model("stanford-bunny.obj")) {
            test::skip("stanford-bunny.obj is not on the model search path");
            return;
        }
        auto fine = asset::load_mesh_spec("stanford-bunny.obj");
        REQUIRE(fine.ok());
        for (uint32_t target : {1000u, 2000u, 5000u}) {
            CAPTURE(target);
            auto d = mesh::decimate(fine.value().mesh, {target, true}, "bunny");
            REQUIRE(d.ok());
            const mesh::TriangleMesh& c = d.value().mesh;
            // Every directed edge once: the topology stage's invariant.
            std::set<std::pair<uint32_t, uint32_t>> directed;
            bool twice = false;
            for (const auto& t : c.triangles)
                for (int k = 0; k < 3; ++k) twice = twice || !directed.insert({t[k], t[(k + 1) % 3]}).second;
            CHECK(!twice);
            CHECK(vertex_distance(fine.value().mesh, c) < 0.02f);  // quadric collapse on a sphere: within a fiftieth of its radius
            // No sliver the topology invariants would reject (under 1/1000 of the mean area).
            double mean = 0.0;
            std::vector<double> area;
            for (const auto& t : c.triangles) {
                area.push_back(0.5 * double((c.positions[t[1]] - c.positions[t[0]]).cross(c.positions[t[2]] - c.positions[t[0]]).norm()));
                mean += area.back();
            }
            mean /= double(area.size());
            CHECK(*std::min_element(area.begin(), area.end()) >= 1e-3 * mean);
        }
    }
}
