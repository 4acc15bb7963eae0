#include "demo/hud.h"

#include <algorithm>
#include <cmath>
#include <cstring>

// A header of static functions written in C's loose style: quiet about it, here only.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wsign-conversion"
#pragma GCC diagnostic ignored "-Wold-style-cast"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wdouble-promotion"
#pragma GCC diagnostic ignored "-Wuseless-cast"
#pragma GCC diagnostic ignored "-Wsign-compare"
#include <stb/stb_easy_font.h>
#pragma GCC diagnostic pop

namespace pbdsplat::demo {

namespace {
void blend(core::ImageRgba8& image, int x, int y, Rgba c) {
    if (x < 0 || y < 0 || x >= int(image.width) || y >= int(image.height) || c.a <= 0.0f) return;
    uint8_t* p = image.at(uint32_t(x), uint32_t(y));
    const float keep = 1.0f - c.a;
    const float src[4] = {c.r * c.a, c.g * c.a, c.b * c.a, c.a};
    for (int k = 0; k < 4; ++k) p[k] = uint8_t(std::clamp(std::lround(src[k] * 255.0f + p[k] * keep), 0L, 255L));
}

// stb_easy_font writes quads of four vertices (x, y, z, colour: 16 bytes each).
struct Quad {
    float x0, y0, x1, y1;
};
std::vector<Quad> glyph_quads(const std::string& text) {
    std::vector<char> buffer(std::max<size_t>(1024, text.size() * 300));
    std::string copy = text;
    const int quads = stb_easy_font_print(0.0f, 0.0f, copy.data(), nullptr, buffer.data(), int(buffer.size()));
    std::vector<Quad> out;
    for (int q = 0; q < quads; ++q) {
        float v[16];
        std::memcpy(v, buffer.data() + size_t(q) * 64, sizeof(v));
        out.push_back({v[0], v[1], v[8], v[9]});  // corners 0 and 2
    }
    return out;
}
} // namespace

void clear(core::ImageRgba8& image) { std::fill(image.pixels.begin(), image.pixels.end(), uint8_t(0)); }

void fill_rect(core::ImageRgba8& image, int x, int y, int w, int h, Rgba color) {
    const int x0 = std::max(0, x), y0 = std::max(0, y);
    const int x1 = std::min(int(image.width), x + w), y1 = std::min(int(image.height), y + h);
    for (int py = y0; py < y1; ++py)
        for (int px = x0; px < x1; ++px) blend(image, px, py, color);
}

void draw_line(core::ImageRgba8& image, Vec2f a, Vec2f b, float thickness, Rgba color) {
    const float length = (b - a).norm();
    const int steps = std::max(1, int(std::ceil(length)));
    const int r = std::max(1, int(std::lround(thickness * 0.5f)));
    for (int i = 0; i <= steps; ++i) {
        const Vec2f p = a + (b - a) * (float(i) / float(steps));
        fill_rect(image, int(p.x()) - r / 2, int(p.y()) - r / 2, r, r, color);
    }
}

Vec2f text_size(const std::string& text, int scale) {
    std::string copy = text;
    return {float(stb_easy_font_width(copy.data()) * scale), float(stb_easy_font_height(copy.data()) * scale)};
}

Vec2f draw_text(core::ImageRgba8& image, int x, int y, const std::string& text, Rgba color, int scale) {
    for (const Quad& q : glyph_quads(text))
        fill_rect(image, x + int(q.x0 * float(scale)), y + int(q.y0 * float(scale)), int((q.x1 - q.x0) * float(scale)),
                  int((q.y1 - q.y0) * float(scale)), color);
    return text_size(text, scale);
}

void draw_panel(core::ImageRgba8& image, int x, int y, const std::vector<std::string>& lines, Rgba color, int scale) {
    const int line_height = 12 * scale;
    int width = 0;
    for (const std::string& l : lines) width = std::max(width, int(text_size(l, scale).x()));
    fill_rect(image, x, y, width + 8 * scale, int(lines.size()) * line_height + 6 * scale, {0.0f, 0.0f, 0.0f, 0.6f});
    for (size_t i = 0; i < lines.size(); ++i) draw_text(image, x + 4 * scale, y + 4 * scale + int(i) * line_height, lines[i], color, scale);
}

} // namespace pbdsplat::demo
