#include "pbdsplat/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace pbdsplat::cli {
namespace {

std::string fmt(const char* f, double v) {
    char buf[64];
    std::snprintf(buf, sizeof(buf), f, v);
    return buf;
}

std::string escape(const std::string& s) {
    std::string o;
    for (char c : s) {
        if (c == '<') o += "&lt;";
        else if (c == '>') o += "&gt;";
        else if (c == '&') o += "&amp;";
        else o += c;
    }
    return o;
}

constexpr const char* k_colors[] = {"#d62728", "#1f77b4", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2"};

} // namespace

std::string render_svg(const PlotSpec& spec, int width, int height) {
    const double left = 80, right = 180, top = 40, bottom = 60;
    auto tx = [&](double v) { return spec.log_x ? std::log10(v) : v; };
    auto ty = [&](double v) { return spec.log_y ? std::log10(v) : v; };
    double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
    for (const auto& s : spec.series)
        for (size_t i = 0; i < s.x.size(); ++i) {
            if ((spec.log_x && s.x[i] <= 0) || (spec.log_y && s.y[i] <= 0)) continue;
            x0 = std::min(x0, tx(s.x[i])), x1 = std::max(x1, tx(s.x[i]));
            y0 = std::min(y0, ty(s.y[i])), y1 = std::max(y1, ty(s.y[i]));
        }
    if (!(x1 >= x0)) x0 = 0, x1 = 1;
    if (!(y1 >= y0)) y0 = 0, y1 = 1;
    if (spec.log_x) x0 = std::floor(x0), x1 = std::max(std::ceil(x1), x0 + 1);
    if (spec.log_y) y0 = std::floor(y0), y1 = std::max(std::ceil(y1), y0 + 1);
    if (x1 == x0) x1 = x0 + 1;
    if (y1 == y0) y1 = y0 + 1;
    const double pw = width - left - right, ph = height - top - bottom;
    auto px = [&](double v) { return left + (tx(v) - x0) / (x1 - x0) * pw; };
    auto py = [&](double v) { return top + ph - (ty(v) - y0) / (y1 - y0) * ph; };

    std::string svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + std::to_string(width) + "\" height=\"" +
                      std::to_string(height) + "\" font-family=\"sans-serif\" font-size=\"12\">\n";
    svg += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    svg += "<text x=\"" + fmt("%.0f", left) + "\" y=\"24\" font-size=\"15\">" + escape(spec.title) + "</text>\n";
    // Grid and ticks at each decade (log) or at five even steps.
    auto ticks = [](double a, double b, bool log) {
        std::vector<double> t;
        if (log)
            for (double e = a; e <= b + 1e-9; e += 1) t.push_back(e);
        else
            for (int i = 0; i <= 5; ++i) t.push_back(a + (b - a) * i / 5.0);
        return t;
    };
    for (double e : ticks(x0, x1, spec.log_x)) {
        const double v = spec.log_x ? std::pow(10.0, e) : e;
        const double x = px(v);
        svg += "<line x1=\"" + fmt("%.1f", x) + "\" y1=\"" + fmt("%.1f", top) + "\" x2=\"" + fmt("%.1f", x) + "\" y2=\"" +
               fmt("%.1f", top + ph) + "\" stroke=\"#ddd\"/>\n";
        svg += "<text x=\"" + fmt("%.1f", x) + "\" y=\"" + fmt("%.1f", top + ph + 18) + "\" text-anchor=\"middle\">" +
               fmt("%g", v) + "</text>\n";
    }
    for (double e : ticks(y0, y1, spec.log_y)) {
        const double v = spec.log_y ? std::pow(10.0, e) : e;
        const double y = py(v);
        svg += "<line x1=\"" + fmt("%.1f", left) + "\" y1=\"" + fmt("%.1f", y) + "\" x2=\"" + fmt("%.1f", left + pw) +
               "\" y2=\"" + fmt("%.1f", y) + "\" stroke=\"#ddd\"/>\n";
        svg += "<text x=\"" + fmt("%.1f", left - 6) + "\" y=\"" + fmt("%.1f", y + 4) + "\" text-anchor=\"end\">" +
               fmt("%g", v) + "</text>\n";
    }
    svg += "<rect x=\"" + fmt("%.1f", left) + "\" y=\"" + fmt("%.1f", top) + "\" width=\"" + fmt("%.1f", pw) +
           "\" height=\"" + fmt("%.1f", ph) + "\" fill=\"none\" stroke=\"#333\"/>\n";
    svg += "<text x=\"" + fmt("%.1f", left + pw / 2) + "\" y=\"" + fmt("%.1f", double(height) - 16) +
           "\" text-anchor=\"middle\">" + escape(spec.x_label) + "</text>\n";
    svg += "<text transform=\"translate(18," + fmt("%.1f", top + ph / 2) + ") rotate(-90)\" text-anchor=\"middle\">" +
           escape(spec.y_label) + "</text>\n";
    for (size_t k = 0; k < spec.series.size(); ++k) {
        const PlotSeries& s = spec.series[k];
        const char* color = k_colors[k % (sizeof(k_colors) / sizeof(k_colors[0]))];
        std::string points;
        for (size_t i = 0; i < s.x.size(); ++i) {
            if ((spec.log_x && s.x[i] <= 0) || (spec.log_y && s.y[i] <= 0)) continue;
            points += fmt("%.1f", px(s.x[i])) + "," + fmt("%.1f", py(s.y[i])) + " ";
            svg += "<circle cx=\"" + fmt("%.1f", px(s.x[i])) + "\" cy=\"" + fmt("%.1f", py(s.y[i])) + "\" r=\"3.5\" fill=\"" +
                   color + "\"/>\n";
            if (i < s.labels.size())
                svg += "<text x=\"" + fmt("%.1f", px(s.x[i]) + 5) + "\" y=\"" + fmt("%.1f", py(s.y[i]) - 5) +
                       "\" font-size=\"10\" fill=\"" + color + "\">" + escape(s.labels[i]) + "</text>\n";
        }
        svg += "<polyline points=\"" + points + "\" fill=\"none\" stroke=\"" + color + "\" stroke-width=\"1.5\"/>\n";
        const double ly = top + 16 + 18 * double(k);
        svg += "<line x1=\"" + fmt("%.1f", left + pw + 12) + "\" y1=\"" + fmt("%.1f", ly) + "\" x2=\"" +
               fmt("%.1f", left + pw + 32) + "\" y2=\"" + fmt("%.1f", ly) + "\" stroke=\"" + color + "\" stroke-width=\"2\"/>\n";
        svg += "<text x=\"" + fmt("%.1f", left + pw + 38) + "\" y=\"" + fmt("%.1f", ly + 4) + "\">" + escape(s.name) + "</text>\n";
    }
    svg += "</svg>\n";
    return svg;
}

} // namespace pbdsplat::cli
