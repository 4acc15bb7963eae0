#include "scene/check_figures.h"

#include <algorithm>

#include "scene/scene_check.h"

namespace pbdsplat::scene {

namespace {

struct FigureOf {
    CheckFigure figure;
    double (*of)(const CheckReport&);
    bool needs_device = false;  // -1 in the report when not measured
};

const std::vector<FigureOf>& figure_table() {
    static const std::vector<FigureOf> t = {
        {{"shape_error_max", "the worst piece's shape error, any frame"}, [](const CheckReport& r) { return r.shape_error_max; }},
        {{"shape_error_before_topology", "the same before the first cut or tear"},
         [](const CheckReport& r) { return r.shape_error_before_topology; }},
        {{"stretch_max", "the longest edge over its rest length (or the mean rest edge, if longer), the most: a spike or sheet shot out of the body"},
         [](const CheckReport& r) { return r.stretch_max; }},
        {{"strays_max", "splats floating away from the surface, the most in a frame"},
         [](const CheckReport& r) { return double(r.strays_max); }},
        {{"hole_ratio_max", "share of the surface's pixels the splats leave open"}, [](const CheckReport& r) { return r.hole_ratio_max; }, true},
        {{"thin_ratio_max", "share of the surface's inner pixels the splats cover less than 0.9 (the background dimly through)"},
         [](const CheckReport& r) { return r.thin_ratio_max; }, true},
        {{"iou_min", "splat silhouette over the mesh's (intersection over union), the least"},
         [](const CheckReport& r) { return r.iou_min; }, true},
        {{"speck_ratio_max", "share of dark specks through the front surface"}, [](const CheckReport& r) { return r.speck_ratio_max; }, true},
        {{"shading_error_max", "splat shading against the lit mesh"}, [](const CheckReport& r) { return r.shading_error_max; }, true},
        {{"color_error_max", "splat colour against the model's own look"}, [](const CheckReport& r) { return r.color_error_max; }, true},
        {{"edge_excess_max", "share of the front where the splats draw an edge the lit mesh lacks (seams, rims, mottling)"},
         [](const CheckReport& r) { return r.edge_excess_max; }, true},
        {{"spacing_within_min", "share of boundary samples spaced within [0.7 h, 1.4 h] along the surface"},
         [](const CheckReport& r) { return r.spacing_within_min; }},
        {{"spacing_within_3d_min", "the same, nearest neighbour in space"}, [](const CheckReport& r) { return r.spacing_within_3d_min; }},
        {{"pieces", "connected pieces at the end"}, [](const CheckReport& r) { return double(r.pieces); }},
        {{"tears", "tears at the end"}, [](const CheckReport& r) { return double(r.tears); }},
        {{"volume_error_max", "the worst piece's volume error"}, [](const CheckReport& r) { return r.volume_error_max; }},
        {{"penetration_max", "the deepest particle inside another piece, over h"}, [](const CheckReport& r) { return r.penetration_max; }},
        {{"crossing_ratio_max", "share of the triangles passing through another (a fold through itself, a torn skin through another piece), the most"},
         [](const CheckReport& r) { return r.crossing_ratio_max; }},
        {{"tilt_max", "the most a model's vertical turned, degrees"}, [](const CheckReport& r) { return r.tilt_max; }},
        {{"height_ratio_min", "the least height over the rest height"}, [](const CheckReport& r) { return r.height_ratio_min; }},
        {{"rip_growth", "the openings' length 2 s after the first tear over their length then (0: no tear)"},
         [](const CheckReport& r) { return r.rip_growth; }},
        {{"burst_volume_ratio", "the least volume within 2 s of the first tear over the volume then (1: no tear)"},
         [](const CheckReport& r) { return r.burst_volume_ratio; }},
        {{"pull_stretch", "a drag's grabbed part at its longest along the pull before a tear, over its length then (0: no drag)"},
         [](const CheckReport& r) { return r.pull_stretch; }},
        {{"speed_rms_end", "the free particles' RMS speed at the end, m/s (a pile at rest: 0)"},
         [](const CheckReport& r) { return r.speed_rms_end; }},
        {{"volume_ratio_min", "the least enclosed volume over the volume at load (cut loops closed by their drawn faces, other openings by fans)"},
         [](const CheckReport& r) { return r.volume_ratio_min; }},
        {{"smallest_piece_min", "triangles in the smallest piece any sample saw"},
         [](const CheckReport& r) { return double(r.smallest_piece_min); }},
        {{"gaussians", "Gaussians at the end"}, [](const CheckReport& r) { return double(r.gaussians); }},
        // The work a frame draws: bounded near today's count, a change that multiplies the samples fails.
        {{"gaussians_max", "the most Gaussians any measured frame drew"}, [](const CheckReport& r) { return double(r.gaussians_max); }},
    };
    return t;
}

} // namespace

std::span<const CheckFigure> check_figures() {
    static const std::vector<CheckFigure> names = [] {
        std::vector<CheckFigure> n;
        for (const FigureOf& f : figure_table()) n.push_back(f.figure);
        return n;
    }();
    return names;
}

bool is_check_figure(std::string_view name) {
    const auto& t = figure_table();
    return std::any_of(t.begin(), t.end(), [&](const FigureOf& f) { return name == f.figure.name; });
}

std::optional<double> check_figure(const CheckReport& report, std::string_view name) {
    for (const FigureOf& f : figure_table()) {
        if (name != f.figure.name) continue;
        const double v = f.of(report);
        if (f.needs_device && v < 0.0) return std::nullopt;
        return v;
    }
    return std::nullopt;
}

std::vector<ExpectOutcome> hold_to_expect(const ExpectDesc& expect, const CheckReport& report) {
    std::vector<ExpectOutcome> out;
    for (const ExpectBound& b : expect.bounds) {
        ExpectOutcome o{b, check_figure(report, b.figure), true};
        if (o.value) o.met = b.at_least ? *o.value >= b.limit : *o.value <= b.limit;
        out.push_back(o);
    }
    return out;
}

} // namespace pbdsplat::scene
