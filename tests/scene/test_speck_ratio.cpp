#include <doctest/doctest.h>

#include "passes/coverage.h"

using namespace pbdsplat;

namespace {
core::ImageRgba8 filled(uint32_t w, uint32_t h, uint8_t r, uint8_t g, uint8_t b, uint8_t a) {
    core::ImageRgba8 img;
    img.width = w;
    img.height = h;
    img.pixels.resize(size_t(w) * h * 4);
    for (size_t i = 0; i < size_t(w) * h; ++i) img.pixels[i * 4] = r, img.pixels[i * 4 + 1] = g, img.pixels[i * 4 + 2] = b, img.pixels[i * 4 + 3] = a;
    return img;
}
} // namespace

TEST_SUITE("scene/speck_ratio") {
    TEST_CASE("the speck ratio is 0 on the lit mesh itself and counts one dark pixel") {
        const core::ImageRgba8 lit = filled(40, 30, 200, 90, 80, 255);
        const core::ImageRgba8 mask = filled(40, 30, 255, 255, 255, 255);
        CHECK(passes::speck_ratio(lit, lit, mask) == 0.0);
        core::ImageRgba8 splats = lit;
        uint8_t* p = &splats.pixels[(size_t(12) * 40 + 7) * 4];
        p[0] = 60, p[1] = 20, p[2] = 20;  // darker than half the mesh's luminance
        core::ImageRgba8 marked;
        CHECK(passes::speck_ratio(splats, lit, mask, &marked) == doctest::Approx(1.0 / 1200.0));
        CHECK(marked.pixels[(size_t(12) * 40 + 7) * 4 + 1] == 0);  // painted magenta
        // Only slightly darker (shading differences): not a speck.
        p[0] = 150, p[1] = 70, p[2] = 60;
        CHECK(passes::speck_ratio(splats, lit, mask) == 0.0);
    }

    TEST_CASE("pixels outside the mesh, or where its inside is seen, are not counted") {
        const core::ImageRgba8 lit = filled(10, 10, 200, 200, 200, 255);
        const core::ImageRgba8 dark = filled(10, 10, 0, 0, 0, 255);
        core::ImageRgba8 mask = filled(10, 10, 255, 255, 255, 0);  // nothing of the mesh
        CHECK(passes::speck_ratio(dark, lit, mask) == 0.0);
        mask = filled(10, 10, 0, 255, 255, 255);  // all of it the inside, through an opening
        CHECK(passes::speck_ratio(dark, lit, mask) == 0.0);
        mask = filled(10, 10, 255, 255, 255, 255);
        CHECK(passes::speck_ratio(dark, lit, mask) == 1.0);
    }

    TEST_CASE("the shading error is 0 on the lit mesh, the mean brightness difference otherwise, and ignores the rest") {
        const core::ImageRgba8 lit = filled(20, 10, 100, 100, 100, 255);
        core::ImageRgba8 mask = filled(20, 10, 255, 255, 255, 255);
        CHECK(passes::shading_error(lit, lit, mask) == 0.0);
        // Half the pixels 51 levels brighter (0.2), the other half unchanged: 0.1 on average.
        core::ImageRgba8 splats = lit;
        for (size_t i = 0; i < 100; ++i) splats.pixels[i * 4] = splats.pixels[i * 4 + 1] = splats.pixels[i * 4 + 2] = 151;
        CHECK(passes::shading_error(splats, lit, mask) == doctest::Approx(0.1));
        // Brighter or darker counts alike; pixels off the mesh's front not at all.
        for (size_t i = 0; i < 100; ++i) splats.pixels[i * 4] = splats.pixels[i * 4 + 1] = splats.pixels[i * 4 + 2] = 49;
        CHECK(passes::shading_error(splats, lit, mask) == doctest::Approx(0.1));
        for (size_t i = 0; i < 100; ++i) mask.pixels[i * 4 + 3] = 0;
        CHECK(passes::shading_error(splats, lit, mask) == 0.0);
    }
}
