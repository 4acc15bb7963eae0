#include <doctest/doctest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "core/math.h"
#include "splat/sort.h"

using namespace pbdsplat;

TEST_SUITE("splat/sort") {
    TEST_CASE("far to near: the order a stable comparison sort of the view depths gives, ties in file order, streams along") {
        // Depths on both sides of the eye (negative and positive view z), many exact ties.
        std::mt19937 rng(3);
        std::uniform_int_distribution<int> coarse(-40, 40);
        std::vector<splat::GaussianRecord> records(5000);
        std::vector<splat::GaussianShape> shapes(records.size());
        for (size_t i = 0; i < records.size(); ++i) {
            records[i].position[0] = float(coarse(rng)) * 0.1f;
            records[i].position[1] = float(coarse(rng)) * 0.1f;
            records[i].position[2] = float(coarse(rng)) * 0.25f;  // ties: few distinct depths
            records[i].color[0] = uint8_t(i & 255), records[i].color[1] = uint8_t(i >> 8);
            shapes[i].axes_half[0] = core::float_to_half(float(i));
        }
        const Mat4f view = math::look_at(Vec3f(0.3f, 0.2f, 2.0f), Vec3f(0.0f, 0.0f, 0.0f), Vec3f(0.0f, 1.0f, 0.0f));
        std::vector<uint32_t> expected(records.size());
        for (uint32_t i = 0; i < expected.size(); ++i) expected[i] = i;
        const Vec4f row = view.row(2);
        const auto depth = [&](uint32_t i) {
            const auto& p = records[i].position;
            return row.x() * p[0] + row.y() * p[1] + row.z() * p[2] + row.w();
        };
        std::stable_sort(expected.begin(), expected.end(), [&](uint32_t a, uint32_t b) { return depth(a) < depth(b); });
        CHECK(depth(expected.front()) < 0.0f);
        CHECK(depth(expected.back()) > 0.0f);  // some behind the eye too

        std::vector<splat::GaussianRecord> sorted = records;
        std::vector<splat::GaussianShape> sorted_shapes = shapes;
        std::vector<float> stream(records.size());
        for (size_t i = 0; i < stream.size(); ++i) stream[i] = float(i);
        splat::SortScratch scratch;
        splat::sort_far_to_near(sorted, sorted_shapes, view, scratch);
        splat::reorder_like_last_sort(scratch, stream);
        size_t wrong = 0;
        for (size_t k = 0; k < expected.size(); ++k) {
            const uint32_t want = expected[k];
            const uint32_t got = uint32_t(sorted[k].color[0]) | uint32_t(sorted[k].color[1]) << 8;
            wrong += got != want || stream[k] != float(want) || sorted_shapes[k].axes_half[0] != shapes[want].axes_half[0];
        }
        CHECK(wrong == 0);
    }
}
