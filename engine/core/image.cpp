#include "core/image.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>

#include <stb_image.h>
#include <stb_image_write.h>

namespace pbdsplat::core {

Status write_png(const std::string& path, const ImageRgba8& image, bool fast) {
    if (image.width == 0 || image.height == 0) return make_error(path, 0, "refusing to write an empty image");
    // stb's level is a global; every caller sets it, so no write inherits another's.
    static std::mutex level_mutex;
    std::lock_guard lock(level_mutex);
    stbi_write_png_compression_level = fast ? 1 : 8;
    stbi_write_force_png_filter = fast ? 1 : -1;  // "sub" alone: no trial of every filter per row
    if (!stbi_write_png(path.c_str(), int(image.width), int(image.height), 4, image.pixels.data(),
                        int(image.width * 4)))
        return make_error(path, 0, "cannot write PNG (does the directory exist and is it writable?)");
    return Status::success();
}

Result<ImageRgba8> read_image(const std::string& path) {
    int w = 0, h = 0, n = 0;
    stbi_uc* data = stbi_load(path.c_str(), &w, &h, &n, 4);
    if (!data) {
        const char* why = stbi_failure_reason();
        return make_error(path, 0, std::string("cannot read image: ") + (why ? why : "unknown reason"));
    }
    ImageRgba8 img{static_cast<uint32_t>(w), static_cast<uint32_t>(h)};
    std::copy(data, data + img.pixels.size(), img.pixels.begin());
    stbi_image_free(data);
    return img;
}

Result<ImageDiff> compare_images(const ImageRgba8& a, const ImageRgba8& b, uint32_t threshold) {
    if (a.width != b.width || a.height != b.height)
        return make_error("images differ in size: " + std::to_string(a.width) + "x" + std::to_string(a.height) +
                          " against " + std::to_string(b.width) + "x" + std::to_string(b.height));
    ImageDiff d;
    d.visual = ImageRgba8(a.width, a.height);
    double sq = 0.0;
    size_t over = 0;
    const size_t n = size_t(a.width) * a.height;
    for (size_t i = 0; i < n; ++i) {
        uint32_t worst = 0;
        for (int c = 0; c < 4; ++c) {
            const int diff = std::abs(int(a.pixels[i * 4 + size_t(c)]) - int(b.pixels[i * 4 + size_t(c)]));
            worst = std::max(worst, uint32_t(diff));
            if (c < 3) sq += double(diff) * diff;
            d.visual.pixels[i * 4 + size_t(c)] = c < 3 ? uint8_t(std::min(255, diff * 8)) : 255;
        }
        d.max_channel_diff = std::max(d.max_channel_diff, worst);
        if (worst > threshold) ++over;
    }
    const double mse = sq / double(n * 3);
    d.psnr_db = mse == 0.0 ? std::numeric_limits<double>::infinity() : 10.0 * std::log10(255.0 * 255.0 / mse);
    d.share_over = double(over) / double(n);
    return d;
}

Result<double> mean_luminance_change(const ImageRgba8& a, const ImageRgba8& b) {
    if (a.width != b.width || a.height != b.height)
        return make_error("images differ in size: " + std::to_string(a.width) + "x" + std::to_string(a.height) +
                          " against " + std::to_string(b.width) + "x" + std::to_string(b.height));
    double sum = 0.0;
    const size_t n = size_t(a.width) * a.height;
    for (size_t i = 0; i < n; ++i) {
        const uint8_t* p = &a.pixels[i * 4];
        const uint8_t* q = &b.pixels[i * 4];
        const double ya = 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
        const double yb = 0.2126 * q[0] + 0.7152 * q[1] + 0.0722 * q[2];
        sum += std::abs(ya - yb) / 255.0;
    }
    return n ? sum / double(n) : 0.0;
}

ImageRgba8 downsample(const ImageRgba8& big, uint32_t factor) {
    ImageRgba8 out(big.width / factor, big.height / factor);
    const uint32_t area = factor * factor;
    for (uint32_t y = 0; y < out.height; ++y)
        for (uint32_t x = 0; x < out.width; ++x)
            for (int c = 0; c < 4; ++c) {
                uint32_t sum = 0;
                for (uint32_t dy = 0; dy < factor; ++dy)
                    for (uint32_t dx = 0; dx < factor; ++dx) sum += big.at(x * factor + dx, y * factor + dy)[c];
                out.at(x, y)[c] = uint8_t((sum + area / 2) / area);
            }
    return out;
}

} // namespace pbdsplat::core
