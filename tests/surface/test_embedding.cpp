#include <doctest/doctest.h>

#include "mesh/decimate.h"
#include "mesh/procedural.h"
#include "sim/soft_body.h"
#include "surface/boundary_particles.h"
#include "surface/embedding.h"

using namespace pbdsplat;

namespace {
struct TwoResolutions {
    mesh::TriangleMesh fine;
    sim::SoftBody body;
    surface::BoundaryParticles samples;
    surface::EmbeddingStats stats;
};

TwoResolutions make(uint32_t coarse_vertices) {
    TwoResolutions t;
    t.fine = mesh::icosphere(5);
    // Bumps, so the fine surface is not the coarse one with more vertices.
    for (Vec3f& p : t.fine.positions) p *= 1.0f + 0.04f * std::sin(9.0f * p.x()) * std::cos(7.0f * p.y());
    auto coarse = mesh::decimate(t.fine, {coarse_vertices, true}, "bumpy sphere");
    REQUIRE(coarse.ok());
    sim::SoftBodyDesc desc;
    auto body = sim::make_soft_body(coarse.value().mesh, desc);
    REQUIRE(body.ok());
    t.body = std::move(body.value());
    const float h = surface::spacing(t.fine, 0.5f);
    const auto points = surface::sample_points(t.fine, t.body.rest_positions, {h, 1});
    surface::embed_points(points, t.body.rest_positions, t.body.triangles, t.body.normals, t.samples, &t.stats);
    return t;
}
} // namespace

TEST_SUITE("surface/embedding") {
    TEST_CASE("embedded samples reproduce the fine surface exactly in the rest pose") {
        TwoResolutions t = make(400);
        REQUIRE(t.samples.size() > 10000);
        const std::vector<Vec3f> at_rest = t.samples.position;
        surface::update_boundary_particles(t.body.triangles, t.body.particles.x, t.body.normals, t.samples);
        const float diag = mesh::bounds(t.fine).diagonal();
        float worst = 0.0f;
        for (size_t i = 0; i < at_rest.size(); ++i) worst = std::max(worst, (t.samples.position[i] - at_rest[i]).norm());
        CHECK(worst <= 1e-5f * diag);
        CHECK(t.stats.fallback == 0);
        // The bumps are carried by the offsets, not flattened onto the coarse triangles.
        CHECK(t.stats.max_offset > 0.005f);
        // Normals in the rest pose are the fine surface's.
        float normal_error = 0.0f;
        for (size_t i = 0; i < t.samples.size(); ++i) normal_error = std::max(normal_error, t.samples.normal[i].norm() - 1.0f);
        CHECK(std::abs(normal_error) < 1e-4f);
    }

    TEST_CASE("after a rigid motion of the coarse mesh the fine samples move rigidly") {
        TwoResolutions t = make(400);
        surface::update_boundary_particles(t.body.triangles, t.body.particles.x, t.body.normals, t.samples);
        const std::vector<Vec3f> p0 = t.samples.position, n0 = t.samples.normal;
        const Mat3f r = Eigen::AngleAxisf(0.9f, Vec3f(0.3f, 1.0f, -0.4f).normalized()).toRotationMatrix();
        const Vec3f move(0.5f, -2.0f, 1.25f);
        std::vector<Vec3f> normals = t.body.normals;
        for (size_t i = 0; i < t.body.particle_count(); ++i) {
            t.body.particles.x[i] = sim::to4(r * sim::xyz(t.body.particles.x[i]) + move);
            normals[i] = r * normals[i];
        }
        surface::update_boundary_particles(t.body.triangles, t.body.particles.x, normals, t.samples);
        float worst = 0.0f, worst_n = 0.0f;
        for (size_t i = 0; i < p0.size(); ++i) {
            worst = std::max(worst, (t.samples.position[i] - (r * p0[i] + move)).norm());
            worst_n = std::max(worst_n, (t.samples.normal[i] - r * n0[i]).norm());
        }
        CHECK(worst < 1e-5f);
        CHECK(worst_n < 1e-4f);
    }

    TEST_CASE("dropping samples keeps every per-sample array aligned") {
        TwoResolutions t = make(300);
        const size_t n = t.samples.size();
        const std::vector<float> offsets = t.samples.offset;
        const size_t dropped = t.samples.keep_if([](size_t i) { return i % 3 != 0; });
        CHECK(dropped == (n + 2) / 3);
        REQUIRE(t.samples.offset.size() == t.samples.size());
        REQUIRE(t.samples.local_normal.size() == t.samples.size());
        CHECK(t.samples.offset[0] == offsets[1]);
        CHECK(t.samples.offset[1] == offsets[2]);
        CHECK(t.samples.offset[2] == offsets[4]);
    }
}
