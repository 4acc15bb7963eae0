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

    TEST_CASE("edge excess: 0 for the mesh's own image or a smooth change of tone; counts a ragged seam and scales") {
        // A lit mesh with a smooth gradient of its own.
        const uint32_t w = 60, h = 40;
        core::ImageRgba8 lit = filled(w, h, 0, 0, 0, 255);
        for (uint32_t y = 0; y < h; ++y)
            for (uint32_t x = 0; x < w; ++x) {
                uint8_t* p = &lit.pixels[(size_t(y) * w + x) * 4];
                p[0] = p[1] = p[2] = uint8_t(60 + 2 * x);
            }
        const core::ImageRgba8 mask = filled(w, h, 255, 255, 255, 255);
        CHECK(passes::edge_excess(lit, lit, mask) == 0.0);
        // Another tone everywhere, and a slow ramp on top: no structure added.
        core::ImageRgba8 toned = lit;
        for (uint32_t y = 0; y < h; ++y)
            for (uint32_t x = 0; x < w; ++x) {
                uint8_t* p = &toned.pixels[(size_t(y) * w + x) * 4];
                p[0] = p[1] = p[2] = uint8_t(p[0] + 20 + y / 4);
            }
        CHECK(passes::edge_excess(toned, lit, mask) == 0.0);
        // A ragged seam: a row band whose pixels alternate 20 brighter and not.
        core::ImageRgba8 seam = lit;
        for (uint32_t y = 18; y < 22; ++y)
            for (uint32_t x = 0; x < w; x += 2) {
                uint8_t* p = &seam.pixels[(size_t(y) * w + x) * 4];
                p[0] = p[1] = p[2] = uint8_t(p[0] + 20);
            }
        const double seam_share = passes::edge_excess(seam, lit, mask);
        CHECK(seam_share > 0.05);  // every other column brightened: about half the edges
        CHECK(seam_share < 0.25);  // the band, not the whole front
        // Scales everywhere: every other pixel of every row.
        core::ImageRgba8 scales = lit;
        for (uint32_t y = 0; y < h; ++y)
            for (uint32_t x = y % 2; x < w; x += 2) {
                uint8_t* p = &scales.pixels[(size_t(y) * w + x) * 4];
                p[0] = p[1] = p[2] = uint8_t(p[0] + 20);
            }
        CHECK(passes::edge_excess(scales, lit, mask) > 0.9);  // every other pixel: nearly every edge
        // Nothing of the mesh: nothing to judge.
        CHECK(passes::edge_excess(scales, lit, filled(w, h, 255, 255, 255, 0)) == 0.0);
    }
}
