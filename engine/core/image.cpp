#include "core/image.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <stb_image.h>
#include <stb_image_write.h>

namespace pbdsplat::core {

Status write_png(const std::string& path, const ImageRgba8& image) {
    if (image.width == 0 || image.height == 0) return make_error(path, 0, "refusing to write an empty image");
    if (!stbi_write_png(path.c_str(), int(image.width), int(image.height), 4, image.pixels.data(),
                        int(image.width * 4)))
        return make_error(path, 0, "cannot write PNG (does the directory exist and is it writable?)");
    return Status::success();
}

Result<ImageRgba8> read_png(const std::string& path) {
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

} // namespace pbdsplat::core
