#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "splat/gaussian_record.h"
#include "splat/mapping.h"

using namespace pbdsplat;

TEST_SUITE("splat/gaussian_record") {
    TEST_CASE("half floats round trip within half precision") {
        // Normal range: relative error at most 2^-11.
        for (float f : {1.0f, -2.5f, 0.0123f, 65504.0f, 6.2e-5f}) {
            const float back = splat::half_to_float(splat::float_to_half(f));
            CHECK(std::abs(back - f) <= std::abs(f) * 0.000489f);
        }
        // Subnormal range: absolute error at most half a step (2^-25).
        for (float f : {0.0f, 3.0e-6f, -1.0e-5f, 4.0e-8f}) {
            const float back = splat::half_to_float(splat::float_to_half(f));
            CHECK(std::abs(back - f) <= 2.99e-8f);  // half a step of the subnormal range, 2^-25
        }
        CHECK(std::isinf(splat::half_to_float(splat::float_to_half(1e6f))));
        CHECK(std::isnan(splat::half_to_float(splat::float_to_half(std::numeric_limits<float>::quiet_NaN()))));
    }

    TEST_CASE("a record's model rides in its normal's lowest bits, moving the normal by under 1e-3 rad") {
        std::mt19937 rng(5);
        std::normal_distribution<float> g;
        float worst = 0.0f;
        for (int i = 0; i < 20000; ++i) {
            Vec3f n(g(rng), g(rng), g(rng));
            if (i < 6) n = Vec3f::Zero(), n[i % 3] = i < 3 ? 1.0f : -1.0f;  // the octahedron's corners: components at +-1
            n.normalize();
            splat::GaussianRecord r = splat::make_record(Vec3f::Zero(), n, {});
            const uint32_t model = uint32_t(i) % (SPLAT_ENV_CENTERS + 3);
            splat::set_model(r, model);
            REQUIRE(splat::record_model(r) == std::min<uint32_t>(model, SPLAT_ENV_CENTERS - 1));  // the last holds the rest
            // The shaders read the component as a snorm float, which takes -32768 to -1 as -32767.
            CHECK(r.normal_oct[0] > -32768);
            CHECK(r.normal_oct[1] > -32768);
            worst = std::max(worst, std::acos(std::clamp(splat::decode_octahedral(r.normal_oct).dot(n), -1.0f, 1.0f)));
        }
        MESSAGE("the normal moved by at most " << worst << " rad");
        CHECK(worst < 1e-3f);  // measured 6.9e-4 rad (where the octahedron folds, at -z), 6.3e-5 without the model
    }

    TEST_CASE("the in-range half conversion rounds to nearest like the full one and flushes subnormals") {
        std::mt19937 rng(11);
        std::uniform_real_distribution<float> exponent(-14.0f, 15.99f), sign(-1.0f, 1.0f);
        size_t differ = 0;
        for (int i = 0; i < 100000; ++i) {
            const float f = std::copysign(std::exp2(exponent(rng)), sign(rng));
            const uint16_t fast = core::float_to_half_in_range(f), full = splat::float_to_half(f);
            CHECK(std::abs(splat::half_to_float(fast) - f) <= std::abs(f) * 0.000489f);
            differ += fast != full ? 1 : 0;  // only an exact tie may round the other way
        }
        CHECK(differ <= 10);
        CHECK(splat::half_to_float(core::float_to_half_in_range(65504.0f)) == 65504.0f);
        CHECK(core::float_to_half_in_range(0.0f) == 0);
        CHECK(core::float_to_half_in_range(3.0e-6f) == 0);        // subnormal in half: zero
        CHECK(core::float_to_half_in_range(-3.0e-6f) == 0x8000);  // keeping its sign
    }

    TEST_CASE("octahedral normals decode within 1e-4 radians") {
        std::mt19937 rng(7);
        std::normal_distribution<float> g;
        float worst = 0.0f;
        for (int i = 0; i < 20000; ++i) {
            const Vec3f n = Vec3f(g(rng), g(rng), g(rng)).normalized();
            int16_t e[2];
            splat::encode_octahedral(n, e);
            const Vec3f d = splat::decode_octahedral(e);
            worst = std::max(worst, std::atan2(n.cross(d).norm(), n.dot(d)));  // acos loses precision near 0
        }
        MESSAGE("worst octahedral error: " << worst << " rad");
        CHECK(worst < 1e-4f);
    }

    TEST_CASE("a record carries what the mapping put in") {
        splat::Appearance a;
        a.albedo = Vec3f(1.0f, 0.5f, 0.0f);
        a.opacity_logit = 2.0f;
        a.scale = 0.03f;
        const auto r = splat::make_record(Vec3f(1, 2, 3), Vec3f(0, 0, -1), a, 0.5f);
        CHECK(r.position[0] == 1.0f);
        CHECK(r.position[2] == 3.0f);
        CHECK(splat::decode_octahedral(r.normal_oct).z() == doctest::Approx(-1.0f));
        CHECK(int(r.color[0]) == 255);
        CHECK(int(r.color[1]) == 128);
        CHECK(int(r.color[3]) == 128);
        CHECK(splat::half_to_float(r.scale_half) == doctest::Approx(0.03f).epsilon(1e-3));
        CHECK(splat::half_to_float(r.opacity_half) == doctest::Approx(2.0f));
    }
}

TEST_SUITE("splat/gaussian_record") {
    TEST_CASE("stretch-aware scale: the triangle's largest stretch, never below 1 or above 3, slivers left alone") {
        const std::vector<Vec3f> rest = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}, {3, 0, 0}, {2.5f, 1e-4f, 0}};
        const std::vector<mesh::Triangle> triangles = {{0, 1, 2}, {3, 4, 5}};
        splat::StretchScale s(rest, triangles);
        auto with = [&](std::vector<Vec3f> p) {
            std::vector<Vec4f> x;
            for (const Vec3f& q : p) x.emplace_back(q.x(), q.y(), q.z(), 0.0f);
            s.update(x, triangles);
        };
        std::vector<Vec3f> p = rest;
        p[1] = {2, 0, 0};  // stretched twice along x
        with(p);
        CHECK(s.triangle(0) == doctest::Approx(2.0f));
        CHECK(s.vertex(1) == doctest::Approx(2.0f));
        p[1] = {0.5f, 0, 0};  // compressed: splats do not shrink
        with(p);
        CHECK(s.triangle(0) == doctest::Approx(1.0f));
        p[1] = {10, 0, 0};  // torn far apart: capped
        with(p);
        CHECK(s.triangle(0) == doctest::Approx(3.0f));
        // The sliver's apex moves by 1e-2: a hundredfold "stretch" of a degenerate frame.
        p = rest;
        p[5] = {2.5f, 1e-2f, 0};
        with(p);
        CHECK(s.triangle(1) == doctest::Approx(1.0f));
    }
}
