#include <doctest/doctest.h>
#include <cstring>

#include <cmath>
#include <limits>

#include "mesh/procedural.h"
#include "splat/mapping.h"
#include "splat/normal_field.h"
#include "surface/boundary_particles.h"

using namespace pbdsplat;

namespace {
std::vector<Vec4f> as_points(const mesh::TriangleMesh& m) {
    std::vector<Vec4f> x;
    for (const Vec3f& p : m.positions) x.emplace_back(p.x(), p.y(), p.z(), 1.0f);
    return x;
}

// The record of a splat at p with normal n, its curvature taken from dn/dx.
Vec3f stored_turn(const Vec3f& p, const Vec3f& n, const Mat3f& dndx, float limit = 1e3f) {
    splat::GaussianRecord r = splat::make_record(p, n, splat::Appearance{});
    splat::encode_curvature(dndx, limit, r);
    return splat::decode_curvature(r);
}
} // namespace

TEST_SUITE("splat/normal_field") {
    TEST_CASE("on a sphere of radius R the normal turns by 1/R per unit length in every tangent direction") {
        const float radius = 2.0f;
        const mesh::TriangleMesh m = mesh::icosphere(4, radius);
        const std::vector<Vec4f> x = as_points(m);
        std::vector<Vec3f> normals;
        for (const Vec3f& p : m.positions) normals.push_back(p.normalized());
        splat::NormalField field;
        field.update(x, normals, m.triangles, true);
        REQUIRE(field.has_vertices());
        size_t checked = 0;
        for (uint32_t t = 0; t < m.triangles.size(); t += 7) {
            const auto& tri = m.triangles[t];
            const Vec3f c = (m.positions[tri[0]] + m.positions[tri[1]] + m.positions[tri[2]]) / 3.0f;
            const Vec3f k = stored_turn(c, c.normalized(), field.triangle(t));
            // xx and yy: 1/R; xy: none (the shape operator of a sphere is isotropic).
            CHECK(k.x() == doctest::Approx(1.0f / radius).epsilon(0.03));
            CHECK(k.z() == doctest::Approx(1.0f / radius).epsilon(0.03));
            CHECK(std::abs(k.y()) < 0.01f / radius);
            ++checked;
        }
        for (uint32_t v = 0; v < m.positions.size(); v += 5) {
            const Vec3f k = stored_turn(m.positions[v], normals[v], field.vertex(v));
            CHECK(k.x() == doctest::Approx(1.0f / radius).epsilon(0.03));
            CHECK(k.z() == doctest::Approx(1.0f / radius).epsilon(0.03));
            CHECK(std::abs(k.y()) < 0.01f / radius);
        }
        CHECK(checked > 100);
    }

    TEST_CASE("a cylinder turns the normal across its axis only") {
        // A strip of a cylinder of radius 1 about z: the turn is 1 across, 0 along the axis, so
        // the stored 2x2 has trace 1 and determinant 0 whichever tangent frame it is stored in.
        mesh::TriangleMesh m;
        std::vector<Vec3f> normals;
        const int around = 24, along = 6;
        for (int j = 0; j <= along; ++j)
            for (int i = 0; i <= around / 4; ++i) {
                const float a = float(i) * 2.0f * float(M_PI) / float(around);
                m.positions.emplace_back(std::cos(a), std::sin(a), 0.2f * float(j));
                normals.emplace_back(std::cos(a), std::sin(a), 0.0f);
            }
        const uint32_t row = uint32_t(around / 4 + 1);
        for (uint32_t j = 0; j < uint32_t(along); ++j)
            for (uint32_t i = 0; i + 1 < row; ++i) {
                const uint32_t a = j * row + i, b = a + 1, c = a + row, d = c + 1;
                m.triangles.push_back({a, b, d});
                m.triangles.push_back({a, d, c});
            }
        splat::NormalField field;
        field.update(as_points(m), normals, m.triangles, false);
        CHECK_FALSE(field.has_vertices());
        for (uint32_t t = 0; t < m.triangles.size(); ++t) {
            const auto& tri = m.triangles[t];
            const Vec3f c = (m.positions[tri[0]] + m.positions[tri[1]] + m.positions[tri[2]]) / 3.0f;
            const Vec3f n = Vec3f(c.x(), c.y(), 0.0f).normalized();
            const Vec3f k = stored_turn(c, n, field.triangle(t));
            // The linear field over a chord is a little weaker than the circle's curvature.
            CHECK(k.x() + k.z() == doctest::Approx(1.0f).epsilon(0.03));
            CHECK(std::abs(k.x() * k.z() - k.y() * k.y()) < 0.02f);
        }
    }

    TEST_CASE("a plane, a sliver and a non-finite turn store nothing; the limit caps the turn") {
        mesh::TriangleMesh m;
        m.positions = {Vec3f(0, 0, 0), Vec3f(1, 0, 0), Vec3f(0, 1, 0), Vec3f(2, 1e-7f, 0)};
        m.triangles = {{0, 1, 2}, {0, 1, 3}};
        std::vector<Vec3f> normals(4, Vec3f::UnitZ());
        splat::NormalField field;
        field.update(as_points(m), normals, m.triangles, true);
        CHECK(field.triangle(0).isZero());
        CHECK(field.vertex(2).isZero());
        // Bent normals on the sliver: its inverse would be huge; it turns nothing instead.
        normals[3] = Vec3f(1, 0, 1).normalized();
        field.update(as_points(m), normals, m.triangles, true);
        CHECK(field.triangle(1).isZero());

        Mat3f nan = Mat3f::Identity();
        nan(0, 0) = std::numeric_limits<float>::quiet_NaN();
        const Vec3f k_nan = stored_turn(Vec3f::Zero(), Vec3f::UnitZ(), nan);
        CHECK(std::isfinite(k_nan.x()));
        CHECK(k_nan.x() == 0.0f);
        const Vec3f capped = stored_turn(Vec3f::Zero(), Vec3f::UnitZ(), 50.0f * Mat3f::Identity(), splat::curvature_limit(0.1f));
        CHECK(capped.x() == doctest::Approx(10.0f).epsilon(0.002));
        CHECK(capped.z() == doctest::Approx(10.0f).epsilon(0.002));
    }

    TEST_CASE("the tangent frame is orthonormal about the normal on both sides of its helper-axis switch") {
        for (float nx : {0.0f, 0.5f, 0.8999f, 0.9001f, 0.99f, -0.95f, 1.0f}) {
            const Vec3f n = Vec3f(nx, std::sqrt(std::max(0.0f, 1.0f - nx * nx)) * 0.6f,
                                  std::sqrt(std::max(0.0f, 1.0f - nx * nx)) * 0.8f)
                                .normalized();
            Vec3f t1, t2;
            splat::tangent_frame(n, t1, t2);
            CHECK(std::abs(t1.norm() - 1.0f) < 1e-5f);
            CHECK(std::abs(t2.norm() - 1.0f) < 1e-5f);
            CHECK(std::abs(t1.dot(n)) < 1e-5f);
            CHECK(std::abs(t2.dot(n)) < 1e-5f);
            CHECK((t1.cross(t2) - n).norm() < 1e-5f);
        }
    }

    TEST_CASE("map_body gives particles and samples their turn with a field, and none without") {
        const mesh::TriangleMesh m = mesh::icosphere(2, 1.0f);
        const std::vector<Vec4f> x = as_points(m);
        const std::vector<Vec3f> normals = mesh::vertex_normals(m);
        surface::BoundaryParticles samples = surface::sample_surface(m, {0.1f, 3});
        surface::update_boundary_particles(m.triangles, x, normals, samples);
        REQUIRE(samples.size() > 50);
        splat::Appearance look;
        look.scale = 0.05f;
        splat::NormalField field;
        field.update(x, normals, m.triangles, true);
        std::vector<splat::GaussianRecord> with, without;
        splat::map_body(x, normals, {}, m.triangles, &samples, look, nullptr, &field, with);
        splat::map_body(x, normals, {}, m.triangles, &samples, look, nullptr, nullptr, without);
        REQUIRE(with.size() == x.size() + samples.size());
        for (size_t i = 0; i < with.size(); ++i) {
            const Vec3f k = splat::decode_curvature(with[i]);
            // A unit sphere: about 1 per unit in both directions (coarse: the chords shorten it).
            CHECK(k.x() > 0.7f);
            CHECK(k.z() > 0.7f);
            CHECK(k.x() < 1.2f);
            CHECK(splat::decode_curvature(without[i]).isZero());
            // Everything else in the record is the same.
            CHECK(std::memcmp(&with[i], &without[i], offsetof(splat::GaussianRecord, curvature_half)) == 0);
        }
    }
}
