#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
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

// S as a record with normal n carries it (and the shader rebuilds it).
Mat3f stored(const splat::SymmetricCurvature& c, const Vec3f& n = Vec3f::UnitZ()) {
    splat::GaussianRecord r = splat::make_record(Vec3f::Zero(), n, splat::Appearance{});
    splat::set_curvature(c, n, r);
    return splat::decode_curvature(r);
}

// Any unit vector perpendicular to n.
Vec3f tangent_of(const Vec3f& n) { return n.cross(std::abs(n.x()) < 0.9f ? Vec3f::UnitX() : Vec3f::UnitY()).normalized(); }
} // namespace

TEST_SUITE("splat/normal_field") {
    TEST_CASE("on a sphere of radius R a step along the surface turns the normal by 1/R of it, and nothing else") {
        const float radius = 2.0f;
        const mesh::TriangleMesh m = mesh::icosphere(4, radius);
        const std::vector<Vec4f> x = as_points(m);
        std::vector<Vec3f> normals;
        for (const Vec3f& p : m.positions) normals.push_back(p.normalized());
        splat::NormalField field;
        field.update(x, normals, m.triangles, true, 100.0f);
        REQUIRE(field.has_vertices());
        size_t checked = 0;
        for (uint32_t t = 0; t < m.triangles.size(); t += 7) {
            const auto& tri = m.triangles[t];
            const Vec3f n = (m.positions[tri[1]] - m.positions[tri[0]]).cross(m.positions[tri[2]] - m.positions[tri[0]]).normalized();
            const Mat3f s = stored(field.triangle(t), n);
            const Vec3f t1 = tangent_of(n), t2 = n.cross(t1);
            // A sphere's shape operator is 1/R times the identity on the tangent plane.
            CHECK((s * t1 - t1 / radius).norm() < 0.03f / radius);
            CHECK((s * t2 - t2 / radius).norm() < 0.03f / radius);  // the chords of a level-4 sphere: within 3 %
            CHECK((s * n).norm() < 0.01f / radius);  // no turn out of the plane
            ++checked;
        }
        for (uint32_t v = 0; v < m.positions.size(); v += 5) {
            const Mat3f s = stored(field.vertex(v), normals[v]);
            const Vec3f t1 = tangent_of(normals[v]);
            CHECK(t1.dot(s * t1) == doctest::Approx(1.0f / radius).epsilon(0.03));
        }
        CHECK(checked > 100);
    }

    TEST_CASE("a cylinder turns the normal across its axis only") {
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
        field.update(as_points(m), normals, m.triangles, false, 100.0f);
        CHECK_FALSE(field.has_vertices());
        for (uint32_t t = 0; t < m.triangles.size(); ++t) {
            const auto& tri = m.triangles[t];
            const Vec3f c = (m.positions[tri[0]] + m.positions[tri[1]] + m.positions[tri[2]]) / 3.0f;
            const Vec3f around_axis = Vec3f(-c.y(), c.x(), 0.0f).normalized();
            // Stored about the face's normal, the one S leaves alone.
            const Vec3f face = (m.positions[tri[1]] - m.positions[tri[0]]).cross(m.positions[tri[2]] - m.positions[tri[0]]).normalized();
            const Mat3f s = stored(field.triangle(t), face);
            // The linear field over a chord turns a little less than the circle's curvature.
            CHECK(around_axis.dot(s * around_axis) == doctest::Approx(1.0f).epsilon(0.03));
            CHECK((s * Vec3f::UnitZ()).norm() < 0.01f);  // a tangent of the face: about 0
        }
    }

    TEST_CASE("a plane, a sliver and a non-finite turn store nothing; the limit caps the turn") {
        mesh::TriangleMesh m;
        m.positions = {Vec3f(0, 0, 0), Vec3f(1, 0, 0), Vec3f(0, 1, 0), Vec3f(2, 1e-7f, 0)};
        m.triangles = {{0, 1, 2}, {0, 1, 3}};
        std::vector<Vec3f> normals(4, Vec3f::UnitZ());
        splat::NormalField field;
        field.update(as_points(m), normals, m.triangles, true, 100.0f);
        CHECK(stored(field.triangle(0)).isZero());
        CHECK(stored(field.vertex(2)).isZero());
        // Bent normals on the sliver: its inverse would be huge; it turns nothing instead.
        normals[3] = Vec3f(1, 0, 1).normalized();
        field.update(as_points(m), normals, m.triangles, true, 100.0f);
        CHECK(stored(field.triangle(1)).isZero());

        // Stored about +z: the record keeps the xy block and rebuilds the z row from S n = 0.
        Mat3f nan = Mat3f::Identity();
        nan(2, 2) = 0.0f;
        nan(0, 0) = std::numeric_limits<float>::quiet_NaN();
        const Mat3f s_nan = stored(splat::to_symmetric(nan, 10.0f));
        CHECK(s_nan(0, 0) == 0.0f);
        CHECK(s_nan(1, 1) == 1.0f);
        Mat3f big = 50.0f * Mat3f::Identity();
        big(2, 2) = 0.0f;
        const Mat3f capped = stored(splat::to_symmetric(big, splat::curvature_limit(0.1f)));
        CHECK(capped(0, 0) == doctest::Approx(10.0f).epsilon(0.002));
        CHECK(capped(1, 1) == doctest::Approx(10.0f).epsilon(0.002));
        CHECK(capped(0, 1) == 0.0f);
        CHECK(std::abs(capped(2, 2)) < 1e-3f);
    }

    TEST_CASE("a record rebuilds S from three numbers and its normal, whichever axis the normal leans on") {
        // A sphere-like S about each normal: (I - n n^T) / 0.5, stored and rebuilt.
        for (const Vec3f& dir : {Vec3f(1, 0.2f, -0.3f), Vec3f(0.1f, -1, 0.4f), Vec3f(-0.3f, 0.3f, 1), Vec3f(0.577f, 0.577f, 0.578f)}) {
            const Vec3f n = dir.normalized();
            const Mat3f s = (Mat3f::Identity() - n * n.transpose()) / 0.5f;
            const Mat3f back = stored(splat::to_symmetric(s, 100.0f), n);
            CHECK((back - s).norm() < 0.01f);  // stored in 16-bit halves: within 1 %
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
        field.update(x, normals, m.triangles, true, splat::curvature_limit(look.scale));
        std::vector<splat::GaussianRecord> with, without;
        splat::map_body(x, normals, {}, m.triangles, &samples, look, nullptr, &field, with);
        splat::map_body(x, normals, {}, m.triangles, &samples, look, nullptr, nullptr, without);
        REQUIRE(with.size() == x.size() + samples.size());
        for (size_t i = 0; i < with.size(); ++i) {
            const Vec3f n = splat::decode_octahedral(with[i].normal_oct);
            const Vec3f t = tangent_of(n);
            // A unit sphere: about 1 per unit (coarse: the chords and each sample's own normal,
            // up to ten degrees off its face's, move it by a fifth).
            const float turn = t.dot(splat::decode_curvature(with[i]) * t);
            CHECK(turn > 0.7f);  // about 1 per unit, within the fifth the comment names
            CHECK(turn < 1.3f);  // the same
            CHECK(splat::decode_curvature(without[i]).isZero());
            // Everything else in the record is the same.
            CHECK(std::memcmp(&with[i], &without[i], offsetof(splat::GaussianRecord, curvature_half)) == 0);
        }
    }
}
