#include <doctest/doctest.h>

#include "splat/deformed_shape.h"

using namespace pbdsplat;

namespace {
// One right triangle in the xy plane, with one boundary particle at its centroid (normal +z).
struct OneTriangle {
    std::vector<Vec3f> rest = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    std::vector<mesh::Triangle> triangles = {{0, 1, 2}};
    surface::BoundaryParticles samples;
    OneTriangle() {
        samples.triangle = {0};
        samples.bary = {Vec2f(1.0f / 3.0f, 1.0f / 3.0f)};
        samples.position = {Vec3f(1.0f / 3.0f, 1.0f / 3.0f, 0.0f)};
        samples.normal = {Vec3f::UnitZ()};
    }
    // The sample's covariance for the vertex positions `x`, with a record of scale s.
    Eigen::Matrix3f covariance(const std::vector<Vec4f>& x, float s, float* record_scale = nullptr) {
        splat::DeformedShapes d(rest, triangles);
        d.update(x, triangles);
        splat::Appearance a;
        a.scale = s;
        std::vector<splat::GaussianRecord> records = {splat::make_record(samples.position[0], samples.normal[0], a)};
        std::vector<splat::GaussianShape> shapes;
        d.map(0, &samples, records, shapes);
        REQUIRE(shapes.size() == 1);
        if (record_scale) *record_scale = splat::half_to_float(records[0].scale_half);
        const Eigen::Matrix3f axes = splat::shape_axes(shapes[0]);
        return axes * axes.transpose();
    }
};
std::vector<Vec4f> moved(const std::vector<Vec3f>& p, const Eigen::Matrix3f& f) {
    std::vector<Vec4f> x;
    for (const Vec3f& v : p) {
        const Vec3f w = f * v;
        x.emplace_back(w.x(), w.y(), w.z(), 1.0f);
    }
    return x;
}
} // namespace

TEST_SUITE("splat/deformed_shape") {
    TEST_CASE("at rest a surface splat is a flat disc of its own size in the tangent plane") {
        OneTriangle t;
        float reach = 0.0f;
        const Eigen::Matrix3f cov = t.covariance(moved(t.rest, Eigen::Matrix3f::Identity()), 0.1f, &reach);
        const float flat = splat::DeformedShapes::k_flatness;
        CHECK(cov(0, 0) == doctest::Approx(0.01f).epsilon(0.01));
        CHECK(cov(1, 1) == doctest::Approx(0.01f).epsilon(0.01));
        CHECK(cov(2, 2) == doctest::Approx(0.01f * flat * flat).epsilon(0.02));
        CHECK(std::abs(cov(0, 1)) < 1e-4f);
        CHECK(reach == doctest::Approx(0.1f).epsilon(0.01));
    }

    TEST_CASE("stretched along x and rotated, the splat stretches and turns with its triangle") {
        OneTriangle t;
        const Eigen::Matrix3f rot = Eigen::AngleAxisf(0.7f, Vec3f(1, 2, 3).normalized()).toRotationMatrix();
        const Eigen::Matrix3f f = rot * Eigen::Matrix3f(Vec3f(2.0f, 1.0f, 1.0f).asDiagonal());
        t.samples.normal = {rot * Vec3f::UnitZ()};
        float reach = 0.0f;
        const Eigen::Matrix3f cov = t.covariance(moved(t.rest, f), 0.1f, &reach);
        const float flat = splat::DeformedShapes::k_flatness;
        const Eigen::Matrix3f expected = rot * Eigen::Matrix3f(Vec3f(0.04f, 0.01f, 0.01f * flat * flat).asDiagonal()) * rot.transpose();
        CHECK((cov - expected).norm() < 0.01f * expected.norm());  // analytic: the stretched disc, to float rounding
        CHECK(reach == doctest::Approx(0.2f).epsilon(0.01));  // the record's scale is the longest axis
        // Past k_max_stretch the splat stops following.
        const Eigen::Matrix3f far = Vec3f(10.0f, 1.0f, 1.0f).asDiagonal();
        t.samples.normal = {Vec3f::UnitZ()};
        const Eigen::Matrix3f capped = t.covariance(moved(t.rest, far), 0.1f);
        CHECK(std::sqrt(capped(0, 0)) == doctest::Approx(0.1f * splat::DeformedShapes::k_max_stretch).epsilon(0.01));
    }

    TEST_CASE("the growth a round splat takes for its triangle's stretch is not counted again") {
        // map_body grows a sample's record by its triangle's growth; the deformed shape takes the
        // stretch from F, and so from the ungrown size.
        OneTriangle t;
        const Eigen::Matrix3f f = Vec3f(1.6f, 1.0f, 1.0f).asDiagonal();
        const Eigen::Matrix3f plain = t.covariance(moved(t.rest, f), 0.1f);
        t.samples.triangle_growth = {1.6f};
        const Eigen::Matrix3f grown = t.covariance(moved(t.rest, f), 0.1f * 1.6f);
        CHECK((grown - plain).norm() < 0.01f * plain.norm());  // the same to half-float rounding
    }

    TEST_CASE("a collapsed triangle leaves its splat round") {
        OneTriangle t;
        const Eigen::Matrix3f cov = t.covariance(moved(t.rest, Eigen::Matrix3f::Zero()), 0.1f);
        CHECK((cov - 0.01f * Eigen::Matrix3f::Identity()).norm() < 1e-4f);
    }
}
