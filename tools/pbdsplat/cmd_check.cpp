#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "pbdsplat/options.h"
#include "pbdsplat/commands.h"
#include "pbdsplat/gpu_options.h"
#include "pbdsplat/scene_arg.h"
#include "scene/check_figures.h"
#include "scene/scene_check.h"

namespace pbdsplat::cli {

int cmd_check(const std::vector<std::string>& argv) {
    static const CommandSpec command{
        "check", "[SCENE.toml | MODEL]",
        "Runs a scene offscreen (default: the built-in one) and measures every K frames:\n"
        "  shape error   per connected piece, RMS distance of the simulation particles from their rest\n"
        "                shape after the best rigid alignment, over the piece's rest diagonal (worst piece)\n"
        "  strays        Gaussians with no neighbour within 3x the median spacing\n"
        "  hole ratio    share of the deformed surface's raster pixels the splats leave below half alpha\n"
        "  thin ratio    share of its inner pixels (the outline left out) they cover less than 0.9\n"
        "  IoU           silhouette of the splats against that raster\n"
        "  pieces        connected components; volume error |V / (k V0) - 1|, worst piece\n"
        "  specks        share of the raster's pixels where the splats are less than half as bright as\n"
        "                the lit mesh (the background or a hidden surface showing through)\n"
        "  shade         mean absolute difference of the splats' brightness from the lit mesh's over\n"
        "                the raster's pixels (0-1): facets, bright discs and specks alike\n"        "  spacing       share of boundary particles whose nearest neighbour lies in [0.7 h, 1.4 h]:\n"
        "                along the surface (a neighbour facing within 60 degrees, so not the far face\n"
        "                of a sharp fold) and, in the JSON's spacing_within_3d, in space\n"
        "  tilt          per model, degrees its best-fit rotation from the rest pose turns the vertical\n"
        "  height        per model, its height over its rest height (smallest)\n"
        "  smallest      the fewest triangles in any piece (a torn-off fleck)\n"
        "The coverage images are the frame as the scene draws it (footprint, shapes, the far side of\n"
        "a closed body culled, the environment about the body) without the ground.\n",
        with_gpu({whole("frames", "N", 120, 1, 100000, "frames to run").default_from("the scene's [expect] frames, else 120"),
                  flag("ignore-expect", "measure only: do not hold the figures to the scene's [expect] bounds"),
                  whole("every", "K", 10, 1, 100000, "measure every K frames and at the last"),
                  whole("width", "W", 320, 16, 4096, "coverage image width"),
                  whole("height", "H", 180, 16, 4096, "coverage image height"),
                  flag("no-gpu", "skip the coverage images (shape, strays, pieces and volume only)"),
                  text("images", "DIR", "", "write each measured frame's splat image and lit mesh as PNG into DIR")
                      .default_from("none"),
                  save_scene_option(), json_option("one JSON object: shape_error_max, stretch_max (the longest edge over its rest\n"
                              "length), strays_max, hole_ratio_max, thin_ratio_max, iou_min,\n"
                              "speck_ratio_max, shading_error_max, color_error_max, pieces, volume_error_max, penetration_max\n"
                              "(the deepest particle inside another piece, over h), crossing_ratio_max (the share of triangles\n"
                              "passing through another), tilt_max,\n"
                              "height_ratio_min, tears, smallest_piece_min, rip_growth, burst_volume_ratio,\n"
                              "pull_stretch (a drag's grabbed part at its longest along the pull before a tear, over\n"
                              "its length when the pull began), volume_ratio_min, speed_rms_end (the free particles'\n"
                              "RMS speed at the end, m/s) and every measured frame")})};
    const Parsed parsed = parse_command(command, argv);
    if (!parsed.options) return parsed.exit_code;
    const Options& opt = *parsed.options;
    auto sc = load_scene_arg(opt);
    if (!sc.ok()) return fail("check", sc.error().to_string());
    scene::CheckOptions o;
    o.frames = opt.given("frames") || sc->expect.frames == 0 ? opt.whole("frames") : sc->expect.frames;
    o.every = opt.whole("every");
    o.width = opt.whole("width");
    o.height = opt.whole("height");
    if (opt.given("images")) {
        o.images_dir = opt.text("images");
        std::error_code ec;
        std::filesystem::create_directories(o.images_dir, ec);
        if (ec || !std::filesystem::is_directory(o.images_dir))
            return fail("check", "--images " + o.images_dir + ": cannot create that directory");
    }
    std::unique_ptr<gpu::Context> ctx;
    if (!opt.flag("no-gpu")) {
        auto c = open_context(opt);
        if (!c.ok()) return fail("check", c.error().to_string() + " (--no-gpu checks without coverage)");
        ctx = std::move(c).value();
        o.gpu = ctx.get();
    }
    auto report = scene::check_scene(sc.value(), o);
    if (!report.ok()) return fail("check", sc->name + ": " + report.error().to_string());
    if (auto v = close_and_check_validation(std::move(ctx)); !v.ok()) return fail("check", v.error().to_string());
    const scene::CheckReport& r = report.value();
    const std::vector<scene::ExpectOutcome> expect =
        opt.flag("ignore-expect") ? std::vector<scene::ExpectOutcome>{} : scene::hold_to_expect(sc->expect, r);
    std::string broken;
    for (const scene::ExpectOutcome& e : expect)
        if (!e.met)
            broken += "\n  " + e.bound.figure + " = " + std::to_string(*e.value) + ", expected " + (e.bound.at_least ? ">= " : "<= ") +
                      std::to_string(e.bound.limit);
    const int status = broken.empty() ? 0 : fail("check", sc->name + " does not show what its [expect] table claims:" + broken);
    if (opt.flag("json")) {
        nlohmann::json claims = nlohmann::json::array();
        for (const scene::ExpectOutcome& e : expect)
            claims.push_back({{"figure", e.bound.figure}, {"bound", e.bound.at_least ? "at_least" : "at_most"}, {"limit", e.bound.limit},
                              {"value", e.value ? nlohmann::json(*e.value) : nlohmann::json()}, {"met", e.met}});
        nlohmann::json samples = nlohmann::json::array();
        for (const scene::CheckSample& s : r.samples)
            samples.push_back({{"frame", s.frame}, {"time", s.time}, {"cuts", s.cuts}, {"tears", s.tears},
                               {"shape_error", s.shape_error}, {"stretch", s.stretch}, {"strays", s.strays}, {"hole_ratio", s.hole_ratio}, {"thin_ratio", s.thin_ratio},
                               {"iou", s.iou}, {"speck_ratio", s.speck_ratio}, {"shading_error", s.shading_error}, {"color_error", s.color_error}, {"edge_excess", s.edge_excess}, {"spacing_within", s.spacing_within}, {"spacing_within_3d", s.spacing_within_3d}, {"spacing_p05", s.spacing_p05}, {"spacing_p95", s.spacing_p95}, {"area_ratio", s.area_ratio}, {"pieces", s.pieces}, {"particles", s.particles},
                               {"gaussians", s.gaussians}, {"volume_error", s.volume_error}, {"penetration", s.penetration},
                               {"crossing_ratio", s.crossing_ratio}, {"self_crossings", s.self_crossings},
                               {"tilt", s.tilt_degrees}, {"height_ratio", s.height_ratio}, {"smallest_piece_triangles", s.smallest_piece_triangles},
                               {"volume_ratio", s.volume_ratio}, {"open_length", s.open_length},
                               {"speed_rms", s.speed_rms}, {"speed_max", s.speed_max}, {"sleeping", s.sleeping}});
        const nlohmann::json j = {{"scene", sc->name},
                                  {"frames", o.frames},
                                  {"shape_error_max", r.shape_error_max},
                                  {"shape_error_before_topology", r.shape_error_before_topology},
                                  {"strays_max", r.strays_max},
                                  {"stretch_max", r.stretch_max},
                                  {"hole_ratio_max", r.hole_ratio_max},
                                  {"thin_ratio_max", r.thin_ratio_max},
                                  {"iou_min", r.iou_min},
                                  {"speck_ratio_max", r.speck_ratio_max},
                                  {"shading_error_max", r.shading_error_max}, {"color_error_max", r.color_error_max},
                                  {"edge_excess_max", r.edge_excess_max},
                                  {"spacing_within_min", r.spacing_within_min},
                                  {"spacing_within_3d_min", r.spacing_within_3d_min},
                                  {"pieces", r.pieces},
                                  {"volume_error_max", r.volume_error_max},
                                  {"penetration_max", r.penetration_max},
                                  {"crossing_ratio_max", r.crossing_ratio_max},
                                  {"tilt_max", r.tilt_max},
                                  {"height_ratio_min", r.height_ratio_min},
                                  {"tears", r.tears},
                                  {"smallest_piece_min", r.smallest_piece_min},
                                  {"rip_growth", r.rip_growth},
                                  {"burst_volume_ratio", r.burst_volume_ratio},
                                  {"pull_stretch", r.pull_stretch},
                                  {"volume_ratio_min", r.volume_ratio_min},
                                  {"speed_rms_end", r.speed_rms_end},
                                  {"particles", r.particles},
                                  {"gaussians", r.gaussians},
                                  {"gaussians_max", r.gaussians_max},
                                  {"stage_a_ms", r.stage_a_ms},
                                  {"model_vertices", r.model_vertices},
                                  {"simulation_particles", r.simulation_particles},
                                  {"embedding_error", r.embedding_error},
                                  {"invariants_at_load", r.invariants_at_load.empty() ? "ok" : r.invariants_at_load},
                                  {"expect", claims},
                                  {"expect_met", broken.empty()},
                                  {"samples", samples}};
        std::printf("%s\n", j.dump().c_str());
        return status;
    }
    std::printf("%s, %u frames (measured every %u); %zu simulation particles for the model's %zu vertices",
                sc->name.c_str(), o.frames, o.every, r.simulation_particles, r.model_vertices);
    if (r.embedding_error > 0.0) std::printf(" (surface embedded, rest error %.2g of the diagonal)", r.embedding_error);
    std::printf(":\n");
    if (!r.invariants_at_load.empty())
        std::printf("  the mesh as loaded breaks the topology invariants, so cuts and tears ran unchecked: %s\n",
                    r.invariants_at_load.c_str());
    std::printf("  %6s %6s %5s %5s %8s %6s %8s %6s %8s %7s %8s %6s %8s %6s %6s %5s %6s %5s\n", "frame", "time", "cuts", "tears", "shape", "strays",
                "holes%", "IoU", "specks%", "shade", "spacing", "pieces", "volume", "area", "pen/h", "tilt", "height", "small");
    auto percent = [](double v) { return v < 0.0 ? -1.0 : 100.0 * v; };
    for (const scene::CheckSample& s : r.samples)
        std::printf("  %6llu %6.2f %5zu %5zu %8.4f %6zu %8.3f %6.3f %8.3f %7.4f %8.3f %6zu %8.4f %6.3f %6.3f %5.1f %6.3f %5zu\n", (unsigned long long)s.frame,
                    s.time, s.cuts, s.tears, s.shape_error, s.strays, percent(s.hole_ratio), s.iou, percent(s.speck_ratio),
                    s.shading_error, s.spacing_within, s.pieces, s.volume_error, s.area_ratio, s.penetration,
                    s.tilt_degrees, s.height_ratio, s.smallest_piece_triangles);
    std::printf("worst: shape %.4f (%.4f before any cut or tear), edges stretched %.2fx, strays %zu, holes %.3f %%, IoU %.3f, specks %.3f %%,\n"
                "       shading error %.4f, colour error %.4f,\n"
                "       spacing within [0.7 h, 1.4 h] %.3f along the surface, %.3f in space; %zu pieces at the end;\n"
                "       %zu particles, %zu Gaussians; Stage A %.3f ms a frame (median); penetration %.3f h;\n"
                "       triangles through another %.3f %%;\n"
                "       tilt %.1f degrees, height %.3f of rest; %zu tears; smallest piece %zu triangles;\n"
                "       volume %.3f of load at least; 2 s after the first tear: openings %.2fx, volume %.3f;\n"
                "       a pull stretched what it held %.2fx before tearing; at the end the free particles move %.3f m/s\n",
                r.shape_error_max, r.shape_error_before_topology, r.stretch_max, r.strays_max, percent(r.hole_ratio_max), r.iou_min,
                percent(r.speck_ratio_max), r.shading_error_max, r.color_error_max, r.spacing_within_min, r.spacing_within_3d_min, r.pieces, r.particles, r.gaussians, r.stage_a_ms, r.penetration_max, percent(r.crossing_ratio_max),
                r.tilt_max, r.height_ratio_min, r.tears, r.smallest_piece_min, r.volume_ratio_min, r.rip_growth, r.burst_volume_ratio, r.pull_stretch, r.speed_rms_end);
    if (!expect.empty()) std::printf("what the scene's [expect] table claims:\n");
    for (const scene::ExpectOutcome& e : expect) {
        if (e.value)
            std::printf("  %-28s %10.4f %s %-10g %s\n", e.bound.figure.c_str(), *e.value, e.bound.at_least ? ">=" : "<=", e.bound.limit,
                        e.met ? "met" : "BROKEN");
        else
            std::printf("  %-28s %10s %s %-10g not measured (no device)\n", e.bound.figure.c_str(), "-", e.bound.at_least ? ">=" : "<=",
                        e.bound.limit);
    }
    return status;
}

} // namespace pbdsplat::cli
