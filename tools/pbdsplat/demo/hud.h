#pragma once
// Drawing into the overlay image on the CPU: panels, text (stb_easy_font's segment glyphs,
// from Debian's libstb-dev) and the cut stroke. Colours are straight RGBA; the image keeps
// premultiplied alpha, as the overlay pass blends it.
#include <string>
#include <vector>

#include "core/image.h"
#include "core/math.h"

namespace pbdsplat::demo {

struct Rgba {
    float r, g, b, a;
};

void clear(core::ImageRgba8& image);
void fill_rect(core::ImageRgba8& image, int x, int y, int w, int h, Rgba color);
void draw_line(core::ImageRgba8& image, Vec2f a, Vec2f b, float thickness, Rgba color);
// Multi-line text from its top-left corner; `scale` pixels per font unit. Returns its size.
Vec2f draw_text(core::ImageRgba8& image, int x, int y, const std::string& text, Rgba color, int scale = 2);
Vec2f text_size(const std::string& text, int scale = 2);

// A panel of lines with a dark translucent background.
void draw_panel(core::ImageRgba8& image, int x, int y, const std::vector<std::string>& lines, Rgba color, int scale = 2);

} // namespace pbdsplat::demo
