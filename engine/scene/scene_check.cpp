#include "scene/scene_check.h"

#include <algorithm>

#include "scene/coverage.h"
#include "scene/scene_runtime.h"
#include "sim/shape_error.h"
#include "splat/strays.h"
#include "topology/invariants.h"

namespace pbdsplat::scene {

core::Result<CheckReport> check_scene(const Scene& scene, const CheckOptions& o) {
    // Every cut and tear is checked against the mesh invariants, when the mesh as loaded meets
    // them (a model the repair could not make fully manifold is reported, and run unchecked).
    std::string invariants;
    {
        auto probe = load_scene_model(scene);
        if (!probe.ok()) return probe.error();
        if (auto s = topology::check_invariants(probe.value().body); !s.ok()) invariants = s.error().to_string();
    }
    RuntimeOptions ro;  // simulation and mapping only: coverage renders its own pair of images
    ro.keep_records = true;
    ro.check_topology = invariants.empty();
    auto created = SceneRuntime::create(scene, ro);
    if (!created.ok()) return created.error();
    SceneRuntime& rt = *created.value();
    CheckReport report;
    report.invariants_at_load = invariants;
    report.model_vertices = rt.decimation().input_vertices;
    report.simulation_particles = rt.body().particle_count();
    if (rt.fine_surface())
        report.embedding_error = rt.embedding().max_rest_error / std::max(mesh::bounds(*rt.fine_surface()).diagonal(), 1e-12f);
    std::vector<double> stage_a;
    std::vector<Vec3f> centres;
    std::vector<Vec4f> x;
    std::vector<mesh::Triangle> triangles;
    for (uint32_t f = 0; f < o.frames; ++f) {
        PBDSPLAT_TRY(rt.step());
        const FrameStats& st = rt.stats();
        stage_a.push_back(st.apply_forces_ms + st.constraints_ms + st.integrate_normals_ms);
        if ((f + 1) % o.every != 0 && f + 1 != o.frames) continue;
        CheckSample s;
        s.frame = st.frame;
        s.time = st.time;
        s.cuts = st.cuts;
        s.tears = st.tears;
        const sim::ShapeReport shape = sim::shape_report(rt.body());
        s.shape_error = shape.max_error;
        s.pieces = shape.pieces.size();
        for (const sim::PieceShape& p : shape.pieces) s.volume_error = std::max(s.volume_error, p.volume_error);
        s.particles = st.particles;
        s.gaussians = st.gaussians;
        // Every splat drawn (the records), not the particles: strays are what a user sees.
        centres.clear();
        for (const splat::GaussianRecord& r : rt.records()) centres.emplace_back(r.position[0], r.position[1], r.position[2]);
        s.strays = splat::count_strays(centres, rt.spacing()).strays;
        if (o.gpu) {
            rt.deformed_surface(x, triangles);
            render::FrameInputs frame = scene.render.frame;
            frame.camera = rt.camera();
            auto c = measure_coverage(*o.gpu, x, triangles, rt.records(), frame, o.width, o.height);
            if (!c.ok()) return core::make_error("frame " + std::to_string(s.frame) + ": " + c.error().to_string());
            s.hole_ratio = c->hole_ratio;
            s.iou = c->silhouette_iou;
        }
        report.samples.push_back(s);
    }
    for (const CheckSample& s : report.samples) {
        report.shape_error_max = std::max(report.shape_error_max, s.shape_error);
        if (s.cuts == 0 && s.tears == 0) report.shape_error_before_topology = std::max(report.shape_error_before_topology, s.shape_error);
        report.strays_max = std::max(report.strays_max, s.strays);
        report.volume_error_max = std::max(report.volume_error_max, s.volume_error);
        if (s.hole_ratio >= 0.0) {
            report.hole_ratio_max = std::max(report.hole_ratio_max, s.hole_ratio);
            report.iou_min = report.iou_min < 0.0 ? s.iou : std::min(report.iou_min, s.iou);
        }
    }
    if (!report.samples.empty()) {
        report.pieces = report.samples.back().pieces;
        report.particles = report.samples.back().particles;
        report.gaussians = report.samples.back().gaussians;
    }
    if (!stage_a.empty()) {
        std::nth_element(stage_a.begin(), stage_a.begin() + stage_a.size() / 2, stage_a.end());
        report.stage_a_ms = stage_a[stage_a.size() / 2];
    }
    return report;
}

} // namespace pbdsplat::scene
