#include <doctest/doctest.h>

#include <algorithm>

#include "mesh/procedural.h"
#include "mesh/topology.h"
#include "sim/soft_body.h"
#include "surface/edges.h"
#include "topology/cut.h"

using namespace pbdsplat;

namespace {
// Every boundary edge of `triangles` carries edge samples no more than `step` apart (and no
// farther than step/2 from its ends), lying on the edge itself.
void check_edges(std::span<const Vec3f> x, std::span<const mesh::Triangle> triangles, const surface::BoundaryParticles& s,
                 float step) {
    const auto loops = mesh::boundary_loops(triangles, x.size());
    REQUIRE(!loops.empty());
    std::vector<Vec3f> edge_points;
    for (size_t i = 0; i < s.size(); ++i) {
        if (!s.on_edge(i)) continue;
        const Vec2f b = s.bary[i];
        const float w[3] = {1.0f - b.x() - b.y(), b.x(), b.y()};
        REQUIRE(std::count_if(w, w + 3, [](float v) { return std::abs(v) < 1e-6f; }) == 1);  // on an edge
        const auto& t = triangles[s.triangle[i]];
        edge_points.push_back(w[0] * x[t[0]] + w[1] * x[t[1]] + w[2] * x[t[2]]);
    }
    for (const auto& loop : loops)
        for (size_t k = 0; k < loop.size(); ++k) {
            const Vec3f a = x[loop[k]], b = x[loop[(k + 1) % loop.size()]];
            // Points of this edge, by their parameter along it.
            std::vector<float> u{0.0f, 1.0f};
            const float len = (b - a).norm();
            for (const Vec3f& p : edge_points) {
                const float t = (p - a).dot(b - a) / (len * len);
                if (t > 0.0f && t < 1.0f && (a + t * (b - a) - p).norm() < 1e-5f) u.push_back(t);
            }
            std::sort(u.begin(), u.end());
            REQUIRE(u.size() >= 3);  // at least one sample on every boundary edge
            for (size_t j = 1; j + 1 < u.size(); ++j) CHECK((u[j + 1] - u[j]) * len <= step * 1.001f);
            CHECK(u[1] * len <= 0.5f * step * 1.001f);  // the first sample half a step in from the end
        }
}
} // namespace

TEST_SUITE("surface/edges") {
    TEST_CASE("an open sheet's rim gets samples every h/2, with smaller splats") {
        const mesh::TriangleMesh sheet = mesh::grid_sheet(6);
        const float h = 0.05f;
        surface::BoundaryParticles s = surface::sample_surface(sheet, {h, 1});
        const size_t interior = s.size();
        const size_t laid = surface::lay_edge_samples(sheet.positions, sheet.triangles, h, {}, s);
        CHECK(laid > 0);
        CHECK(s.size() == interior + laid);
        for (size_t i = interior; i < s.size(); ++i) CHECK(s.size_of(i) == 0.5f);
        check_edges(sheet.positions, sheet.triangles, s, 0.5f * h);
        // Laying again replaces them rather than adding more.
        CHECK(surface::lay_edge_samples(sheet.positions, sheet.triangles, h, {}, s) == laid);
        CHECK(s.size() == interior + laid);
    }

    TEST_CASE("a cut edge has samples along it at the required spacing") {
        auto body = sim::make_soft_body(mesh::icosphere(3), {});
        REQUIRE(body.ok());
        auto plane = topology::plane_cut(Vec3f(0.0f, 0.1f, 0.0f), Vec3f(0.0f, 1.0f, 0.0f));
        REQUIRE(plane.ok());
        REQUIRE(topology::cut(body.value(), plane.value()).ok());
        const mesh::TriangleMesh rest{body->rest_positions, body->triangles, {}, {}, {}};
        const float h = surface::spacing(rest, 0.5f);
        surface::BoundaryParticles s = surface::sample_surface(rest, {h, 1});
        CHECK(surface::lay_edge_samples(body->rest_positions, body->triangles, h, {}, s) > 0);
        check_edges(body->rest_positions, body->triangles, s, 0.5f * h);
    }
}
