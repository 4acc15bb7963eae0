#include <doctest/doctest.h>

#include <cmath>
#include <stdexcept>

#include "core/math.h"
#include "core/timer.h"

using namespace pbdsplat;

TEST_SUITE("core/math") {
    TEST_CASE("look_at puts the eye at the origin and the target on -z") {
        const Vec3f eye(1.0f, 2.0f, 3.0f), target(-2.0f, 0.5f, 0.0f);
        const Mat4f v = math::look_at(eye, target, Vec3f(0, 1, 0));
        const Vec4f e = v * eye.homogeneous();
        CHECK(e.head<3>().norm() == doctest::Approx(0.0f).epsilon(1e-5));
        const Vec4f t = v * target.homogeneous();
        CHECK(t.x() == doctest::Approx(0.0f).epsilon(1e-5));
        CHECK(t.y() == doctest::Approx(0.0f).epsilon(1e-5));
        CHECK(t.z() == doctest::Approx(-(target - eye).norm()));
        // The rotation part stays orthonormal.
        const Mat3f r = v.block<3, 3>(0, 0);
        CHECK((r * r.transpose() - Mat3f::Identity()).norm() < 1e-5f);
    }

    TEST_CASE("look_at straight along the up vector (a camera above its target) picks an up across the view") {
        for (const Vec3f& eye : {Vec3f(0, 5, 0), Vec3f(0, -5, 0), Vec3f(5, 0, 0)}) {
            const Mat4f v = math::look_at(eye, Vec3f::Zero(), eye.normalized());
            REQUIRE(v.allFinite());
            CHECK((v * eye.homogeneous()).head<3>().norm() < 1e-5f);
            const Vec4f t = v * Vec4f(0, 0, 0, 1);
            CHECK(std::abs(t.x()) < 1e-5f);
            CHECK(std::abs(t.y()) < 1e-5f);
            CHECK(t.z() == doctest::Approx(-5.0f));
            const Mat3f r = v.block<3, 3>(0, 0);
            CHECK((r * r.transpose() - Mat3f::Identity()).norm() < 1e-5f);
        }
        // The eye on the target has no view direction at all: refused.
        CHECK_THROWS_AS(math::look_at(Vec3f::Zero(), Vec3f::Zero(), Vec3f(0, 1, 0)), std::logic_error);
    }

    TEST_CASE("perspective maps near to depth 0, far to 1, and flips y for Vulkan") {
        const float n = 0.1f, f = 50.0f;
        const Mat4f p = math::perspective(math::radians(60.0f), 16.0f / 9.0f, n, f);
        auto ndc = [&](const Vec3f& v) {
            const Vec4f c = p * v.homogeneous();
            return Vec3f(c.head<3>() / c.w());
        };
        CHECK(ndc(Vec3f(0, 0, -n)).z() == doctest::Approx(0.0f).epsilon(1e-6));
        CHECK(ndc(Vec3f(0, 0, -f)).z() == doctest::Approx(1.0f).epsilon(1e-5));
        // A point above the axis lands in the upper half of the image: negative NDC y.
        CHECK(ndc(Vec3f(0, 1, -5)).y() < 0.0f);
        // The top edge of the frustum maps to y = -1.
        const float half = std::tan(math::radians(30.0f)) * 5.0f;
        CHECK(ndc(Vec3f(0, half, -5)).y() == doctest::Approx(-1.0f).epsilon(1e-5));
    }

    TEST_CASE("sigmoid and logit invert each other") {
        for (float x : {-6.0f, -1.0f, 0.0f, 0.5f, 4.0f}) CHECK(math::logit(math::sigmoid(x)) == doctest::Approx(x).epsilon(1e-4));
        CHECK(math::sigmoid(0.0f) == doctest::Approx(0.5f));
    }

    TEST_CASE("floor_to_int agrees with std::floor, negatives and exact integers included") {
        // The grids' cells: a point on a cell's lower face belongs to that cell, one a hair
        // below it to the cell before.
        for (float v : {0.0f, -0.0f, 0.5f, -0.5f, 1.0f, -1.0f, 2.999999f, -2.999999f, 1e6f + 0.5f, -1e6f - 0.5f, 123456.0f, -7.25f}) {
            CHECK(math::floor_to_int(v) == int(std::floor(v)));
            const float below = std::nextafter(v, -1e30f), above = std::nextafter(v, 1e30f);
            CHECK(math::floor_to_int(below) == int(std::floor(below)));
            CHECK(math::floor_to_int(above) == int(std::floor(above)));
        }
        CHECK(math::floor_to_int(-1e-30f) == -1);
        const Eigen::Vector3i c = math::floor_to_int(Vec3f(-0.25f, 3.0f, -4.0f));
        CHECK(c == Eigen::Vector3i(-1, 3, -4));
        // The three-lane form (SSE where built with it) against std::floor, lane by lane.
        const float values[] = {0.0f, -0.0f, 0.5f, -0.5f, 1.0f, -1.0f, 2.999999f, -2.999999f, -1e-30f, 1e6f + 0.5f, -1e6f - 0.5f, -7.25f};
        for (float a : values)
            for (float b : values) {
                const float z = std::nextafter(a, -1e30f);
                const Eigen::Vector3i cell = math::floor_to_int(Vec3f(a, b, z));
                CHECK(cell == Eigen::Vector3i(int(std::floor(a)), int(std::floor(b)), int(std::floor(z))));
            }
    }

    TEST_CASE("median of odd and even sample sets") {
        CHECK(core::median({5.0, 1.0, 3.0}) == 3.0);
        CHECK(core::median({4.0, 1.0, 3.0, 2.0}) == 2.5);
        CHECK(core::median({}) == 0.0);
    }
}
