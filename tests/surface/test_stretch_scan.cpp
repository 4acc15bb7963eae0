#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "mesh/deformation.h"
#include "mesh/procedural.h"
#include "surface/stretch_scan.h"
#include "support/skip.h"

using namespace pbdsplat;

namespace {

// A sphere's triangles under a random deformation, with random bounds around their stretches:
// some lanes quiet, some past each test, some counting frames.
struct Frame {
    mesh::TriangleMesh rest = mesh::icosphere(3);
    std::vector<Vec4f> x;
    std::vector<float> lanes, shrank_large2, shrank_small2, grew_large2, grew_small2, reference2, reference_squeeze2;
    std::vector<int8_t> beyond;
    std::vector<Eigen::Matrix2f> inverse;

    explicit Frame(uint32_t seed) {
        std::mt19937 rng(seed);
        std::uniform_real_distribution<float> u(-1.0f, 1.0f), f(0.5f, 1.5f);
        for (const Vec3f& p : rest.positions) x.emplace_back(p.x() * 1.2f + 0.08f * u(rng), p.y() + 0.08f * u(rng), p.z() * 0.8f + 0.08f * u(rng), u(rng));
        const size_t n = rest.triangles.size();
        lanes.assign(16 * ((n + 3) / 4), 0.0f);
        for (size_t t = 0; t < n; ++t) {
            const auto& c = rest.triangles[t];
            inverse.push_back(mesh::rest_frame_inverse(rest.positions[c[0]], rest.positions[c[1]], rest.positions[c[2]]));
            for (int e = 0; e < 4; ++e) lanes[16 * (t / 4) + 4 * size_t(e) + t % 4] = inverse.back().data()[e];
            shrank_large2.push_back(f(rng) * 0.6f), shrank_small2.push_back(f(rng) * 0.5f);
            grew_large2.push_back(f(rng) * 1.6f), grew_small2.push_back(f(rng) * 1.4f);
            reference2.push_back(f(rng)), reference_squeeze2.push_back(f(rng) * 0.8f);
            beyond.push_back(rng() % 7 == 0 ? int8_t(1 + rng() % 3) : int8_t(0));
        }
    }
    surface::StretchScan scan(std::vector<float>& l2, std::vector<float>& s2) const {
        l2.assign(rest.triangles.size(), -1.0f);
        s2.assign(rest.triangles.size(), -1.0f);
        surface::StretchScan s;
        s.x = x;
        s.triangles = rest.triangles;
        s.rest_lanes = lanes.data();
        s.stretch2 = l2.data(), s.squeeze2 = s2.data();
        s.shrank_large2 = shrank_large2.data(), s.shrank_small2 = shrank_small2.data();
        s.grew_large2 = grew_large2.data(), s.grew_small2 = grew_small2.data();
        s.reference2 = reference2.data(), s.reference_squeeze2 = reference_squeeze2.data();
        s.beyond = beyond.data();
        s.grow2 = 1.21f, s.shrink2 = 0.81f, s.squash2 = 0.5625f, s.unsquash2 = 1.0f / 0.5625f;
        return s;
    }
};

bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

} // namespace

TEST_SUITE("surface/stretch_scan") {
    TEST_CASE("the four-lane scan measures each triangle's stretches and lists the busy ones") {
        const Frame f(5);
        std::vector<float> l2, s2;
        std::vector<uint32_t> busy;
        const size_t scanned = surface::scan_stretches(f.scan(l2, s2), busy, surface::ScanLanes::four);
#if defined(__SSE2__)
        REQUIRE(scanned == f.rest.triangles.size() / 4 * 4);
#else
        REQUIRE(scanned == 0);
#endif
        size_t quiet = 0;
        std::vector<uint32_t> expected;
        for (uint32_t t = 0; t < scanned; ++t) {
            const auto& c = f.rest.triangles[t];
            const Vec3f o = f.x[c[0]].head<3>();
            const mesh::Stretch want = mesh::squared_stretches(f.inverse[t], f.x[c[1]].head<3>() - o, f.x[c[2]].head<3>() - o);
            REQUIRE(l2[t] == doctest::Approx(want.largest).epsilon(1e-5));
            REQUIRE(s2[t] == doctest::Approx(want.smallest).epsilon(1e-4));
            const float ref_sq = std::max(f.reference_squeeze2[t], 1e-12f);
            const bool is_busy = l2[t] < f.shrank_large2[t] || s2[t] < f.shrank_small2[t] || l2[t] > f.grew_large2[t] ||
                                 s2[t] > f.grew_small2[t] || l2[t] > 1.21f * f.reference2[t] || s2[t] > (1.0f / 0.5625f) * ref_sq ||
                                 l2[t] < 0.81f * f.reference2[t] || s2[t] < 0.5625f * ref_sq || f.beyond[t] != 0;
            if (is_busy) expected.push_back(t);
            else ++quiet;
        }
        CHECK(busy == expected);
#if defined(__SSE2__)
        CHECK(quiet > 0);  // the bounds leave some lanes quiet, and some busy
        CHECK(!busy.empty());
#endif
    }

    TEST_CASE("the eight-lane scan gives the four-lane scan's bits") {
        if (!surface::eight_lanes_available()) {
            test::skip("this processor has no AVX; the eight-lane scan is not used here");
            return;
        }
        for (uint32_t seed : {1u, 2u, 3u}) {
            Frame f(seed);
            f.x[7].x() = std::nanf("");  // a broken particle: its triangles come back busy in both
            std::vector<float> l4, s4, l8, s8;
            std::vector<uint32_t> busy4, busy8;
            const size_t n4 = surface::scan_stretches(f.scan(l4, s4), busy4, surface::ScanLanes::four);
            const size_t n8 = surface::scan_stretches(f.scan(l8, s8), busy8, surface::ScanLanes::eight);
            CHECK(n4 == n8);
            CHECK(same_bits(l4, l8));
            CHECK(same_bits(s4, s8));
            CHECK(busy4 == busy8);
        }
    }
}
