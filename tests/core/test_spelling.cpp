#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "core/spelling.h"

using namespace pbdsplat;

TEST_SUITE("core/spelling") {
    TEST_CASE("the nearest name within one edit for a short word, two for a longer one") {
        const std::vector<std::string> names{"frames", "width", "height", "no-gpu", "render", "sort_on", "eta"};
        CHECK(core::nearest_spelling("frame", names) == "frames");     // one dropped
        CHECK(core::nearest_spelling("frmaes", names) == "frames");    // two swapped: one edit
        CHECK(core::nearest_spelling("no_gpus", names) == "no-gpu");   // '_' and '-' alike, one added
        CHECK(core::nearest_spelling("Sort-On", names) == "sort_on");  // case and dashes fold
        CHECK(core::nearest_spelling("hieght", names) == "height");
        CHECK(core::nearest_spelling("rendr", names) == "render");
        CHECK(core::nearest_spelling("etta", names) == "eta");         // a short word: one edit
        CHECK_FALSE(core::nearest_spelling("ea_x", names).has_value());  // two from eta: too far for four letters
        CHECK_FALSE(core::nearest_spelling("wobble", names).has_value());
        CHECK_FALSE(core::nearest_spelling("x", std::vector<std::string>{"y", "z"}).has_value());  // one letter: no likeness
        CHECK_FALSE(core::nearest_spelling("frames", std::vector<std::string>{}).has_value());
    }

    TEST_CASE("the nearest wins, then the first of equals") {
        const std::vector<std::string> names{"iterations", "iteration_x", "substeps"};
        CHECK(core::nearest_spelling("iteration", names) == "iterations");  // 1 edit against 2
        const std::vector<std::string> equals{"mass", "mast"};
        CHECK(core::nearest_spelling("masx", equals) == "mass");
    }
}
