#pragma once
// An 8-bit RGBA image in host memory, and PNG in and out.
#include <cstdint>
#include <string>
#include <vector>

#include "core/result.h"

namespace pbdsplat::core {

struct ImageRgba8 {
    uint32_t width = 0;
    uint32_t height = 0;
    std::vector<uint8_t> pixels;  // row-major, top row first, 4 bytes a pixel

    ImageRgba8() = default;
    ImageRgba8(uint32_t w, uint32_t h) : width(w), height(h), pixels(size_t(w) * h * 4, 0) {}
    uint8_t* at(uint32_t x, uint32_t y) { return pixels.data() + (size_t(y) * width + x) * 4; }
    const uint8_t* at(uint32_t x, uint32_t y) const { return pixels.data() + (size_t(y) * width + x) * 4; }
};

// `fast`: the lightest compression (about three times quicker, files about a third larger),
// for frame sequences that an encoder reads once.
Status write_png(const std::string& path, const ImageRgba8& image, bool fast = false);
// PNG, JPEG, BMP, TGA, GIF or PSD, as 8-bit RGBA (what stb_image decodes).
Result<ImageRgba8> read_image(const std::string& path);

// How far two images of the same size are apart, as the golden-image tests judge them.
struct ImageDiff {
    double psnr_db = 0.0;           // over RGB; +inf when identical
    double share_over = 0.0;        // share of pixels with any channel off by more than the threshold
    uint32_t max_channel_diff = 0;  // largest difference of any channel, 0..255
    ImageRgba8 visual;              // |a - b| amplified, for people to look at
};
Result<ImageDiff> compare_images(const ImageRgba8& a, const ImageRgba8& b, uint32_t threshold);

// Mean absolute difference of Rec. 709 luminance (0..1) between two images of one size: the
// flicker measure of `bench temporal`.
Result<double> mean_luminance_change(const ImageRgba8& a, const ImageRgba8& b);

// Each factor x factor block averaged into one pixel (a supersampled reference brought down to
// the size it is compared at); a partial block at the right or bottom edge is dropped.
ImageRgba8 downsample(const ImageRgba8& big, uint32_t factor);

} // namespace pbdsplat::core
