#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "core/thread_pool.h"
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

TwoResolutions make(uint32_t coarse_vertices, core::ThreadPool* pool = nullptr) {
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
    const auto points = surface::sample_points(t.fine, t.body.rest_positions, {h, 1}, pool);
    surface::embed_points(points, t.body.rest_positions, t.body.triangles, t.body.normals, t.samples, &t.stats, pool);
    return t;
}
} // namespace

TEST_SUITE("surface/embedding") {
    TEST_CASE("sampling and embedding on a pool give the same samples, bit for bit") {
        // Enough darts (about 1.5M) for the sampler's batches to be shared among the threads.
        core::ThreadPool pool(3);
        const TwoResolutions alone = make(400), shared = make(400, &pool);
        REQUIRE(alone.samples.size() > 10000);
        REQUIRE(shared.samples.size() == alone.samples.size());
        size_t differ = 0;
        for (size_t i = 0; i < alone.samples.size(); ++i)
            differ += shared.samples.position[i] != alone.samples.position[i] ||
                      shared.samples.normal[i] != alone.samples.normal[i] ||
                      shared.samples.triangle[i] != alone.samples.triangle[i] ||
                      shared.samples.bary[i] != alone.samples.bary[i] || shared.samples.offset[i] != alone.samples.offset[i] ||
                      shared.samples.local_normal[i] != alone.samples.local_normal[i];
        CHECK(differ == 0);
        CHECK(shared.stats.outside == alone.stats.outside);
        CHECK(shared.stats.fallback == alone.stats.fallback);
        CHECK(shared.stats.max_offset == alone.stats.max_offset);
        CHECK(shared.stats.max_rest_error == alone.stats.max_rest_error);
    }

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

    TEST_CASE("embedded normals turn smoothly across a coarse edge when the coarse mesh folds there") {
        // A flat square of two coarse triangles (diagonal 0-2) carrying fine samples close to
        // both sides of the diagonal. Folding one triangle by 60 degrees about the diagonal tilts
        // the interpolated normals alike on both sides of it; the samples' normals must follow
        // them, not jump by the fold as the faces' normals do.
        const std::vector<Vec3f> rest = {Vec3f(0, 0, 0), Vec3f(1, 0, 0), Vec3f(1, 1, 0), Vec3f(0, 1, 0)};
        const std::vector<mesh::Triangle> triangles = {{0, 1, 2}, {0, 2, 3}};
        const std::vector<Vec3f> rest_normals(4, Vec3f::UnitZ());
        std::vector<surface::SurfacePoint> points;
        const float e = 0.004f;
        for (int k = 1; k < 10; ++k) {
            const float t = 0.1f * float(k);
            points.push_back({Vec3f(t + e, t - e, 0.0f), Vec3f::UnitZ()});  // in triangle 0-1-2
            points.push_back({Vec3f(t - e, t + e, 0.0f), Vec3f::UnitZ()});  // in triangle 0-2-3
        }
        surface::BoundaryParticles samples;
        surface::embed_points(points, rest, triangles, rest_normals, samples);
        REQUIRE(samples.size() == points.size());
        for (size_t i = 0; i < points.size(); i += 2) {
            REQUIRE(samples.triangle[i] == 0);
            REQUIRE(samples.triangle[i + 1] == 1);
        }
        mesh::TriangleMesh folded;
        folded.positions = rest;
        folded.triangles = triangles;
        const Vec3f axis = Vec3f(1, 1, 0).normalized();
        folded.positions[3] = Eigen::AngleAxisf(float(M_PI) / 3.0f, axis) * rest[3];
        const std::vector<Vec3f> normals = mesh::vertex_normals(folded);
        std::vector<Vec4f> x;
        for (const Vec3f& p : folded.positions) x.emplace_back(p.x(), p.y(), p.z(), 1.0f);
        surface::update_boundary_particles(triangles, x, normals, samples);
        const Vec3f face0 = (folded.positions[1] - folded.positions[0]).cross(folded.positions[2] - folded.positions[0]).normalized();
        const Vec3f face1 = (folded.positions[2] - folded.positions[0]).cross(folded.positions[3] - folded.positions[0]).normalized();
        REQUIRE(std::acos(face0.dot(face1)) > 1.0f);  // the fold: 60 degrees between the faces
        float worst = 0.0f;
        for (size_t i = 0; i < samples.size(); i += 2) {
            CHECK(std::abs(samples.normal[i].norm() - 1.0f) < 1e-4f);
            worst = std::max(worst, std::acos(std::clamp(samples.normal[i].dot(samples.normal[i + 1]), -1.0f, 1.0f)));
        }
        // 8 mm apart on a unit square: the interpolated normal turns by under a degree there.
        CHECK(worst < 0.03f);
    }

    TEST_CASE("embedded normals in the rest pose are the fine surface's own") {
        TwoResolutions t = make(400);
        const auto points = surface::sample_points(t.fine, t.body.rest_positions, {surface::spacing(t.fine, 0.5f), 1});
        REQUIRE(points.size() == t.samples.size());
        surface::update_boundary_particles(t.body.triangles, t.body.particles.x, t.body.normals, t.samples);
        float worst = 0.0f;
        for (size_t i = 0; i < points.size(); ++i) worst = std::max(worst, (t.samples.normal[i] - points[i].normal).norm());
        CHECK(worst < 1e-4f);
    }
}
