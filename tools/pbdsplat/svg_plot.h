#pragma once
// A small SVG line plot with logarithmic axes, for benchmark figures in docs/.
#include <string>
#include <vector>

namespace pbdsplat::cli {

struct PlotSeries {
    std::string name;
    std::vector<double> x, y;
    std::vector<std::string> labels;  // optional, one per point
};

struct PlotSpec {
    std::string title, x_label, y_label;
    bool log_x = true, log_y = true;
    std::vector<PlotSeries> series;
};

// The SVG document; points with non-positive coordinates on a log axis are left out.
std::string render_svg(const PlotSpec& spec, int width = 720, int height = 480);

} // namespace pbdsplat::cli
