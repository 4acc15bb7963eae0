#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>

#include "core/image.h"

using namespace pbdsplat;

TEST_SUITE("core/image") {
    TEST_CASE("PNG round trip keeps every byte") {
        core::ImageRgba8 img(7, 5);
        for (size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = uint8_t(i * 37 % 251);
        const auto path = (std::filesystem::temp_directory_path() / "pbdsplat_test_roundtrip.png").string();
        REQUIRE(core::write_png(path, img).ok());
        auto back = core::read_image(path);
        REQUIRE(back.ok());
        CHECK(back->width == 7);
        CHECK(back->height == 5);
        CHECK(back->pixels == img.pixels);
        std::filesystem::remove(path);
    }

    TEST_CASE("reading a missing file names the file") {
        auto r = core::read_image("/nonexistent/pbdsplat.png");
        REQUIRE_FALSE(r.ok());
        CHECK(r.error().to_string().find("/nonexistent/pbdsplat.png") != std::string::npos);
    }

    TEST_CASE("image comparison counts pixels over the threshold and computes PSNR") {
        core::ImageRgba8 a(10, 10), b(10, 10);
        auto same = core::compare_images(a, b, 2);
        REQUIRE(same.ok());
        CHECK(std::isinf(same->psnr_db));
        CHECK(same->share_over == 0.0);

        b.at(3, 4)[1] = 3;  // one channel off by 3 in one pixel of 100
        b.at(5, 5)[0] = 2;  // within the threshold
        auto d = core::compare_images(a, b, 2);
        REQUIRE(d.ok());
        CHECK(d->share_over == doctest::Approx(0.01));
        CHECK(d->max_channel_diff == 3);
        const double mse = (9.0 + 4.0) / 300.0;
        CHECK(d->psnr_db == doctest::Approx(10.0 * std::log10(255.0 * 255.0 / mse)));
    }

    TEST_CASE("images of different sizes do not compare") {
        CHECK_FALSE(core::compare_images(core::ImageRgba8(4, 4), core::ImageRgba8(4, 5), 2).ok());
    }

    TEST_CASE("luminance change is the mean |dY| over pixels, and refuses images of two sizes") {
        core::ImageRgba8 a(4, 2), b(4, 2);
        auto none = core::mean_luminance_change(a, b);
        REQUIRE(none.ok());
        CHECK(none.value() == 0.0);
        for (int c = 0; c < 3; ++c) b.at(1, 1)[c] = 255;  // one white pixel of 8: |dY| = 1 there
        auto one = core::mean_luminance_change(a, b);
        REQUIRE(one.ok());
        CHECK(one.value() == doctest::Approx(1.0 / 8.0));
        CHECK_FALSE(core::mean_luminance_change(a, core::ImageRgba8(2, 4)).ok());
    }

    TEST_CASE("downsampling averages each block with rounding") {
        core::ImageRgba8 big(5, 4);  // the fifth column is a partial block and is dropped
        big.at(0, 0)[0] = 255;
        big.at(1, 1)[0] = 254;  // block (0,0): (255 + 254) / 4 = 127.25 -> 127
        big.at(2, 2)[1] = 2;    // block (1,1): 2 / 4 = 0.5 -> rounds to 1
        big.at(4, 0)[2] = 200;
        const core::ImageRgba8 small = core::downsample(big, 2);
        REQUIRE(small.width == 2);
        REQUIRE(small.height == 2);
        CHECK(small.at(0, 0)[0] == 127);
        CHECK(small.at(1, 1)[1] == 1);
        CHECK(small.at(1, 0)[2] == 0);
    }
}
