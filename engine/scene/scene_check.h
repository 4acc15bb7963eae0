#pragma once
// `pbdsplat check`: runs a scene offscreen and measures, every few frames, whether it shows
// what a user expects of a soft body: that it keeps its shape (per piece), that no splat
// floats away from the surface, that the splats close the surface (hole ratio and silhouette
// IoU against a raster of the same deformed surface), how many pieces there are, and how far
// each piece's volume is from its target, how many dark specks show through the front surface,
// whether the boundary particles keep their spacing, whether any piece lies inside another, and
// how each model stands (its tilt and height against the rest pose).
#include <cstdint>
#include <string>
#include <vector>

#include "core/result.h"
#include "gpu/context.h"
#include "scene/scene.h"

namespace pbdsplat::scene {

struct CheckOptions {
    uint32_t frames = 120;
    uint32_t every = 10;            // measure every this many frames (and the last)
    uint32_t width = 320, height = 180;  // coverage images
    gpu::Context* gpu = nullptr;    // null: no coverage (shape, strays and pieces only)
    std::string images_dir;         // when set: splats, lit mesh and mask of every measured frame, as PNG
};

struct CheckSample {
    uint64_t frame = 0;
    float time = 0.0f;
    size_t cuts = 0, tears = 0;
    double shape_error = 0.0;  // the worst piece
    double stretch = 0.0;      // the longest edge over its rest length (sim::edge_stretch_max)
    size_t strays = 0;
    double hole_ratio = -1.0, iou = -1.0, speck_ratio = -1.0;  // -1: not measured (no GPU)
    double thin_ratio = -1.0;     // passes::Coverage::thin_ratio; -1 as above
    double shading_error = -1.0;  // passes::shading_error; -1 as above
    double color_error = -1.0;    // passes::color_error (against the model's own look); -1 as above
    double edge_excess = -1.0;    // passes::edge_excess (seams, rims, mottling the lit mesh lacks); -1 as above
    // The boundary particles' nearest-neighbour spacing along the surface (the neighbour on the
    // same side of a fold): share within [0.7 h, 1.4 h] (-1: no boundary particles), and its 5th
    // and 95th percentiles in units of h. `spacing_within_3d`: the nearest neighbour in space,
    // whichever side it faces (a sharp fold brings the other sheet closer than h).
    double spacing_within = -1.0, spacing_p05 = -1.0, spacing_p95 = -1.0;
    double spacing_within_3d = -1.0;
    // The deformed surface's area over its rest area (with a device only: the surface is
    // embedded for the coverage images).
    double area_ratio = -1.0;
    size_t pieces = 0, particles = 0, gaussians = 0;
    double volume_error = 0.0;  // the worst piece with a volume constraint
    // The deepest simulation particle inside another closed piece, over the sampling spacing h
    // (sim::deepest_penetration).
    double penetration = 0.0;
    // The share of the live triangles passing through another (sim::surface_crossings): a fold
    // through itself, an open piece through another; within one piece, the crossing pairs.
    double crossing_ratio = 0.0;
    size_t self_crossings = 0;
    // The pose of each model (sim::pose_report): the most its vertical turned, in degrees, and
    // the least height over its rest height; the fewest triangles in a piece.
    double tilt_degrees = 0.0, height_ratio = 1.0;
    size_t smallest_piece_triangles = 0;
    // What the body encloses over what it enclosed at load (open loops closed by fans), and the
    // rest length of its openings in mean rest edges (sim::opening_report).
    double volume_ratio = 1.0, open_length = 0.0;
    // How fast the free particles move (m/s): root mean square and the fastest. A pile that has
    // landed should read near 0: what it keeps is jitter the contact puts in.
    double speed_rms = 0.0, speed_max = 0.0;
    size_t sleeping = 0;  // pieces asleep (sim/sleep.h)
};

struct CheckReport {
    std::vector<CheckSample> samples;
    double shape_error_max = 0.0;
    double shape_error_before_topology = 0.0;  // worst before the first cut or tear
    double stretch_max = 0.0;                  // the most any edge was stretched (CheckSample::stretch)
    size_t strays_max = 0;
    double hole_ratio_max = -1.0, iou_min = -1.0, speck_ratio_max = -1.0, shading_error_max = -1.0, color_error_max = -1.0;
    double edge_excess_max = -1.0;
    double thin_ratio_max = -1.0;
    double spacing_within_min = -1.0, spacing_within_3d_min = -1.0;
    double volume_error_max = 0.0;
    double penetration_max = 0.0;
    double crossing_ratio_max = 0.0;
    double tilt_max = 0.0, height_ratio_min = 1.0;  // degrees; over rest height (see CheckSample)
    size_t smallest_piece_min = 0;  // triangles: the smallest fragment any sample saw
    // A burst, read every frame from the first tear on: the openings' length 2 s after the first
    // tear (or at the end) over their length on that frame, and the least volume in those 2 s over
    // the volume on that frame. Nothing torn reads as no growth (0) and no fall (1).
    double rip_growth = 0.0, burst_volume_ratio = 1.0;
    // A pull, read every frame of a drag until its first tear: the grabbed part's length along the
    // pull at its longest over its length when the pull began (0: nothing pulled).
    double pull_stretch = 0.0;
    double volume_ratio_min = 1.0;  // over the samples
    // The free particles' RMS speed at the last sample (m/s): a scene that ends at rest reads 0.
    double speed_rms_end = 0.0;
    size_t pieces = 0, tears = 0;  // at the end
    size_t particles = 0, gaussians = 0;  // at the end
    size_t gaussians_max = 0;             // the most any measured frame drew: the scene's work
    double stage_a_ms = 0.0;  // median of the frames' Stage A (forces, constraints, integrate)
    // The simulation mesh against the model: the model's vertices, and how exactly the
    // embedded samples reproduce its surface at rest (largest error over the diagonal).
    size_t model_vertices = 0, simulation_particles = 0;
    double embedding_error = 0.0;
    // Empty when the simulation mesh as loaded meets the topology invariants (and every cut
    // and tear was then checked against them); else what it breaks.
    std::string invariants_at_load;
};

core::Result<CheckReport> check_scene(const Scene& scene, const CheckOptions& options);

} // namespace pbdsplat::scene
