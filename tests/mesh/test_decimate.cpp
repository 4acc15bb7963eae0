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

    TEST_CASE("a surface simplified for drawing stays within its error over its own vertices, its open edge kept") {
        const mesh::TriangleMesh sphere = mesh::icosphere(5);  // 20,480 triangles, radius 1
        mesh::TriangleMesh dome{sphere.positions, {}, {}, {}, {}};
        for (const mesh::Triangle& t : sphere.triangles)
            if (sphere.positions[t[0]].y() > 0.0f && sphere.positions[t[1]].y() > 0.0f && sphere.positions[t[2]].y() > 0.0f)
                dome.triangles.push_back(t);
        const float error = 0.005f;
        const std::vector<mesh::Triangle> drawn = mesh::simplify_triangles(dome.positions, dome.triangles, error);
        MESSAGE(dome.triangles.size() << " triangles -> " << drawn.size());
        CHECK(drawn.size() * 4 < dome.triangles.size());
        CHECK(drawn.size() > 20);
        // Every vertex the dome used lies within about the error of what is drawn (meshoptimizer's
        // error is a quadric estimate: on this dome a vertex lay 1.66x it away, so 2x is allowed).
        const mesh::TriangleGrid grid(dome.positions, drawn);
        std::set<uint32_t> used;
        for (const mesh::Triangle& t : dome.triangles) used.insert(t.begin(), t.end());
        float worst = 0.0f;
        for (uint32_t v : used) worst = std::max(worst, grid.distance(dome.positions[v]));
        MESSAGE("farthest vertex " << worst << " (error " << error << ")");
        CHECK(worst <= 2.0f * error);  // measured 1.66x
        // The open edge (edges one triangle uses) is the dome's own, edge for edge.
        const auto border = [](const std::vector<mesh::Triangle>& ts) {
            std::multiset<std::pair<uint32_t, uint32_t>> edges;
            for (const mesh::Triangle& t : ts)
                for (int k = 0; k < 3; ++k) edges.insert(std::minmax(t[size_t(k)], t[size_t((k + 1) % 3)]));
            std::set<std::pair<uint32_t, uint32_t>> once;
            for (const auto& e : edges)
                if (edges.count(e) == 1) once.insert(e);
            return once;
        };
        CHECK(border(drawn) == border(dome.triangles));
        CHECK(mesh::simplify_triangles(dome.positions, dome.triangles, 0.0f) == dome.triangles);  // nothing to simplify within
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
