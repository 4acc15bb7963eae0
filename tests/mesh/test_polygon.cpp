#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "mesh/polygon.h"

using namespace pbdsplat;

namespace {

double total_area(const std::vector<Vec3f>& p, const std::vector<std::array<uint32_t, 3>>& tris) {
    double a = 0.0;
    for (const auto& t : tris) a += 0.5 * double((p[t[1]] - p[t[0]]).cross(p[t[2]] - p[t[0]]).norm());
    return a;
}
Vec3f summed_normal(const std::vector<Vec3f>& p, const std::vector<std::array<uint32_t, 3>>& tris) {
    Vec3f n = Vec3f::Zero();
    for (const auto& t : tris) n += (p[t[1]] - p[t[0]]).cross(p[t[2]] - p[t[0]]);
    return n;
}

} // namespace

TEST_SUITE("mesh/polygon") {
    TEST_CASE("least area: a concave planar outline gets triangles inside it, wound like the outline") {
        // A C: 3 x 3 square without its middle right 1 x 1 notch reaching in 2 (area 9 - 2 = 7).
        const std::vector<Vec3f> c = {{0, 0, 0}, {3, 0, 0}, {3, 1, 0}, {1, 1, 0}, {1, 2, 0}, {3, 2, 0}, {3, 3, 0}, {0, 3, 0}};
        const auto tris = mesh::triangulate_least_area(c);
        CHECK(tris.size() == c.size() - 2);
        CHECK(total_area(c, tris) == doctest::Approx(7.0));
        // Counter-clockwise outline: every triangle faces +z (none turned over across the notch).
        for (const auto& t : tris) CHECK((c[t[1]] - c[t[0]]).cross(c[t[2]] - c[t[0]]).z() > 0.0f);
    }

    TEST_CASE("least area: a loop over two planes folds along their chord") {
        // Two unit squares meeting at a right angle along the x axis (a face cut again across
        // an earlier cut's face): the loop runs over both. Spanning the wedge between them flat
        // would take 2.41; the two faces take 2.
        const std::vector<Vec3f> c = {{0, 0, 1}, {1, 0, 1}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 0}};
        const auto tris = mesh::triangulate_least_area(c);
        CHECK(tris.size() == 4);
        CHECK(total_area(c, tris) == doctest::Approx(2.0).epsilon(1e-5));
        for (const auto& t : tris) {
            // Each triangle lies in one of the two faces: y = 0 or z = 0.
            const bool floor = c[t[0]].y() == 0.0f && c[t[1]].y() == 0.0f && c[t[2]].y() == 0.0f;
            const bool wall = c[t[0]].z() == 0.0f && c[t[1]].z() == 0.0f && c[t[2]].z() == 0.0f;
            CHECK((floor || wall));
        }
    }

    TEST_CASE("least area: the winding follows the loop, so a reversed loop faces the other way") {
        std::vector<Vec3f> c;
        for (int k = 0; k < 12; ++k) c.push_back({std::cos(0.5236f * float(k)), std::sin(0.5236f * float(k)), 0.0f});
        const Vec3f up = summed_normal(c, mesh::triangulate_least_area(c));
        std::reverse(c.begin(), c.end());
        const Vec3f down = summed_normal(c, mesh::triangulate_least_area(c));
        CHECK(up.z() > 0.0f);
        CHECK(down.z() < 0.0f);
        CHECK(up.z() == doctest::Approx(-down.z()));
    }

    TEST_CASE("least area: fewer than three corners give nothing; past the limit the ear clipper takes over") {
        CHECK(mesh::triangulate_least_area(std::vector<Vec3f>{{0, 0, 0}, {1, 0, 0}}).empty());
        std::vector<Vec3f> big;
        for (size_t k = 0; k <= mesh::k_max_least_area_corners; ++k) {
            const float a = 6.2831853f * float(k) / float(mesh::k_max_least_area_corners + 1);
            big.push_back({std::cos(a), std::sin(a), 0.0f});
        }
        const auto tris = mesh::triangulate_least_area(big);
        CHECK(tris.size() == big.size() - 2);
    }

    TEST_CASE("across an older face: each part spans its own plane, where the least area cuts across the wedge") {
        // A unit ball cut by x = 0 (a disc face), then its x > 0 half cut by y = 0: the quarter
        // y > 0 keeps the upper half of the older disc (corners on x = 0) and gets the new half disc
        // on y = 0, meeting it along the chord from (0, 0, -1) to (0, 0, 1), the two corners the
        // second cut made on the older rim. Its face is the two half discs (area pi at the limit).
        constexpr int k = 24;
        std::vector<Vec3f> c;
        std::vector<uint8_t> older;
        const float pi = std::numbers::pi_v<float>;
        c.emplace_back(0.0f, 0.0f, 1.0f), older.push_back(0);  // the chord's ends are new corners
        for (int i = 1; i < k; ++i) {                         // over the top, on x = 0
            const float t = pi * float(i) / float(k);
            c.emplace_back(0.0f, std::sin(t), std::cos(t)), older.push_back(1);
        }
        c.emplace_back(0.0f, 0.0f, -1.0f), older.push_back(0);
        for (int i = 1; i < k; ++i) {  // back round the side, on y = 0
            const float t = pi * float(i) / float(k);
            c.emplace_back(std::sin(t), 0.0f, -std::cos(t)), older.push_back(0);
        }
        const auto on_a_plane = [&](const std::array<uint32_t, 3>& t) {
            const auto all = [&](auto coord) { return std::abs(coord(c[t[0]])) < 1e-6f && std::abs(coord(c[t[1]])) < 1e-6f && std::abs(coord(c[t[2]])) < 1e-6f; };
            return all([](const Vec3f& p) { return p.x(); }) || all([](const Vec3f& p) { return p.y(); });
        };
        const double two_half_discs = double(k) * std::sin(pi / float(k));  // two k-gon halves
        std::vector<uint8_t> parts;
        const auto folded = mesh::triangulate_across_older(c, older, &parts);
        CHECK(folded.size() == c.size() - 2);
        // Each triangle named by its part: the older face's on x = 0 (the run), the cut's on y = 0.
        REQUIRE(parts.size() == folded.size());
        for (size_t t = 0; t < folded.size(); ++t) {
            const auto on_x = [&](uint32_t i) { return std::abs(c[i].x()) < 1e-6f; };
            const bool older_plane = on_x(folded[t][0]) && on_x(folded[t][1]) && on_x(folded[t][2]);
            CHECK(int(parts[t]) == (older_plane ? 1 : 0));
        }
        CHECK(total_area(c, folded) == doctest::Approx(two_half_discs).epsilon(1e-4));
        for (const auto& t : folded) CHECK(on_a_plane(t));
        // Wound like the loop: the x = 0 part faces -x and the y = 0 part faces -y, out of the
        // quarter, as the loop runs.
        for (const auto& t : folded) {
            const Vec3f n = (c[t[1]] - c[t[0]]).cross(c[t[2]] - c[t[0]]);
            CHECK(n.x() + n.y() < 0.0f);
        }
        // The least area over the whole loop cuts across the wedge, through the quarter: less
        // area, off both planes (what left a piece's shell open to the eye).
        const auto least = mesh::triangulate_least_area(c);
        CHECK(total_area(c, least) < 0.95 * two_half_discs);  // cutting across the wedge saves more than 5 %
        CHECK(std::count_if(least.begin(), least.end(), on_a_plane) < long(least.size()));
        // No older corner, or no new one: the least area.
        CHECK(mesh::triangulate_across_older(c, std::vector<uint8_t>(c.size(), 0)) == least);
        CHECK(mesh::triangulate_across_older(c, std::vector<uint8_t>(c.size(), 1)) == least);
    }
}
