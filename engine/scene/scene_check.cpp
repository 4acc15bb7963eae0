#include "scene/scene_check.h"

#include <algorithm>
#include <cmath>
#include <cfloat>
#include <cstdio>

#include "passes/coverage.h"
#include "scene/scene_runtime.h"
#include "sim/opening.h"
#include "sim/crossings.h"
#include "sim/penetration.h"
#include "sim/pose.h"
#include "sim/shape_error.h"
#include "splat/strays.h"
#include "surface/density.h"
#include "surface/spacing_report.h"

namespace pbdsplat::scene {

namespace {
double area_of(std::span<const Vec4f> x, std::span<const mesh::Triangle> triangles) {
    double a = 0.0;
    for (const auto& t : triangles) a += 0.5 * double((x[t[1]] - x[t[0]]).head<3>().cross((x[t[2]] - x[t[0]]).head<3>()).norm());
    return a;
}

// How fast the free particles move, and how many pieces sleep.
void sample_motion(const sim::SoftBody& body, CheckSample& s) {
    const sim::Particles& particles = body.particles;
    double v2 = 0.0;
    size_t moving = 0;
    for (size_t i = 0; i < particles.size(); ++i) {
        if (particles.w[i] <= 0.0f) continue;
        const double v = double(sim::xyz(particles.v[i]).norm());
        v2 += v * v, ++moving, s.speed_max = std::max(s.speed_max, v);
    }
    s.speed_rms = moving ? std::sqrt(v2 / double(moving)) : 0.0;
    s.sleeping = body.sleep.sleeping;
}

// Shape and volume error, strays and sample spacing of the frame the runtime just stepped.
void sample_body_and_splats(const SceneRuntime& rt, double load_volume, CheckSample& s) {
    // Each cut face as drawn and met (folded where a second cut crossed it).
    const auto faces = [&rt](const std::vector<uint32_t>& loop) { return rt.cut_faces().triangles_of(loop); };
    const sim::OpeningReport opening = sim::opening_report(rt.body(), faces);
    s.volume_ratio = load_volume != 0.0 ? opening.volume / load_volume : 1.0;
    s.open_length = opening.open_length;
    const sim::ShapeReport shape = sim::shape_report(rt.body());
    s.penetration = rt.spacing() > 0.0f ? double(sim::deepest_penetration(rt.body(), faces).depth) / double(rt.spacing()) : 0.0;
    const sim::Crossings crossings = sim::surface_crossings(rt.body());
    s.crossing_ratio = crossings.ratio, s.self_crossings = crossings.self_pairs;
    s.shape_error = shape.max_error;
    s.stretch = sim::edge_stretch_max(rt.body());
    s.pieces = shape.pieces.size();
    const sim::PoseReport pose = sim::pose_report(rt.body());
    s.tilt_degrees = pose.tilt_max_degrees;
    s.height_ratio = pose.height_ratio_min;
    s.smallest_piece_triangles = sim::smallest_piece_triangles(rt.body());
    for (const sim::PieceShape& p : shape.pieces) s.volume_error = std::max(s.volume_error, p.volume_error);
    sample_motion(rt.body(), s);
    // Every splat drawn (the records), not the particles: strays are what a user sees.
    std::vector<Vec3f> centres;
    for (const splat::GaussianRecord& r : rt.records()) centres.emplace_back(r.position[0], r.position[1], r.position[2]);
    s.strays = splat::count_strays(centres, rt.spacing()).strays;
    // The boundary particles' spacing (the sampler's and the density control's work), each
    // sample's nearest neighbour sought among every splat that stays drawn: the samples, and the
    // particles where they are splats. The particles are measured only as neighbours: their own
    // spacing is the model's tessellation (suzanne's vertices crowd its eyes and mouth: 43 % of
    // them have another within 0.7 h at rest). Edge samples lie h/2 apart along a boundary on
    // purpose, with smaller splats; retiring samples are leaving because they crowd a neighbour.
    // Along the surface, a neighbour counts on the sample's own side of a fold only: a crumpled
    // balloon folds its triangles flat onto their neighbours, and samples on a fold's two faces,
    // h apart along the surface, come within 0.7 h in space (both figures are reported). The
    // side is the face of the triangle carrying the sample (the interpolated normals of a fold's
    // two faces still agree within 35 degrees on the default balloon's crumpled frames).
    const surface::BoundaryParticles& b = rt.boundary_particles();
    if (b.size() > 1) {
        const sim::SoftBody& body = rt.body();
        auto face_normal = [&](uint32_t t) {
            const mesh::Triangle& c = body.triangles[t];
            const Vec4f& a = body.particles.x[c[0]];
            const Vec3f n = (body.particles.x[c[1]] - a).head<3>().cross((body.particles.x[c[2]] - a).head<3>());
            const float len = n.norm();
            return len > 0.0f ? Vec3f(n / len) : Vec3f::Zero();
        };
        centres.clear();
        std::vector<Vec3f> normals;
        for (size_t i = 0; i < b.size(); ++i)
            if (!b.on_edge(i) && !b.retiring(i)) centres.push_back(b.position[i]), normals.push_back(face_normal(b.triangle[i]));
        const size_t measured = centres.size();
        if (rt.particles_are_splats()) {
            for (const Vec4f& p : body.particles.x) centres.push_back(p.head<3>());
            normals.insert(normals.end(), body.normals.begin(), body.normals.end());
        }
        const surface::SpacingReport sp = surface::spacing_report(centres, rt.spacing(), {0.7f, 1.4f, measured, normals});
        s.spacing_within = sp.within;
        s.spacing_p05 = sp.p05;
        s.spacing_p95 = sp.p95;
        s.spacing_within_3d = surface::spacing_report(centres, rt.spacing(), {0.7f, 1.4f, measured, {}}).within;
    }
}

// A textured model's look as the lit reference draws it: `looks` holds the surface's first
// triangles; the cut faces appended after them take their corners' colours. Returns the
// textures (none where no model has one).
std::vector<render::MeshTexture> reference_textures(TriangleLooks& looks, std::span<const mesh::Triangle> triangles,
                                                    std::span<const Vec3f> colors) {
    if (looks.textures.empty()) return {};
    const size_t first_face = looks.texture.size();
    looks.texture.resize(triangles.size(), -1);
    looks.uv.resize(triangles.size(), {Vec2f::Zero(), Vec2f::Zero(), Vec2f::Zero()});
    looks.tint.resize(triangles.size(), {Vec3f::Ones(), Vec3f::Ones(), Vec3f::Ones()});
    for (size_t t = first_face; t < triangles.size(); ++t)
        for (size_t k = 0; k < 3 && triangles[t][k] < colors.size(); ++k) looks.tint[t][k] = colors[triangles[t][k]];
    return gpu_textures(looks.textures);
}

// Holes, silhouette and specks of the frame as the runtime draws it (its camera, the
// environment about the body, the far side of a closed body culled): what a user would see.
// Without the ground, whose pixels are not the body's.
core::Status sample_coverage(SceneRuntime& rt, const Scene& scene, const CheckOptions& o, double rest_area, CheckSample& s) {
    std::vector<Vec4f> x;
    std::vector<mesh::Triangle> triangles;
    SolidOrder order;
    rt.deformed_surface(x, triangles, &order);
    s.area_ratio = rest_area > 0.0 ? area_of(x, triangles) / rest_area : -1.0;
    // The mesh drawn against the splats closes the pieces with the cut faces, as the splats do.
    std::span<const Vec3f> colors = rt.surface_colors();
    std::vector<Vec3f> with_faces(colors.begin(), colors.end());
    TriangleLooks looks = rt.triangle_looks(triangles);
    // A plain body's cut faces take the colour their splats do (the interior colour where the
    // material has one): the surface in its albedo, each face in its own.
    if (colors.empty() && rt.cut_faces().faces() > 0) with_faces.assign(x.size(), scene.material.color);
    rt.append_cut_faces(x, triangles, with_faces.empty() ? nullptr : &with_faces);
    if (!with_faces.empty()) colors = with_faces;
    render::FrameInputs frame = rt.frame_inputs();
    frame.ground.visible = false;
    frame.style.order = rt.order();  // without a device: the CPU sort, records already in order
    const std::vector<render::MeshTexture> textures = reference_textures(looks, triangles, colors);
    const passes::ReferenceTextures reference{looks.texture, looks.uv, looks.tint, textures};
    // The splats read the textures the runtime gives them: the first SPLAT_MAX_TEXTURES.
    const passes::SplatTexturing texturing{rt.texcoords(),
                                           std::span(textures).first(std::min<size_t>(textures.size(), SPLAT_MAX_TEXTURES))};
    // The splats hidden by what the frames' occluders draw on this device.
    std::vector<Vec4f> occluder_x;
    std::vector<mesh::Triangle> occluder_triangles;
    SolidOrder occluder_order;
    const float simplify = rt.occluder_simplify_error(o.gpu->caps());
    if (simplify > 0.0f) {
        rt.occluder_surface(occluder_x, occluder_triangles, occluder_order, simplify);
        rt.append_cut_faces(occluder_x, occluder_triangles, nullptr);
    }
    const passes::OccluderInput occluders{occluder_x, occluder_triangles, occluder_order.one_sided(occluder_triangles.size())};
    auto c = passes::measure_coverage(*o.gpu, x, triangles, rt.records(), frame, o.width, o.height, scene.material.color, rt.shapes(),
                                      colors, textures.empty() ? nullptr : &reference, rt.texcoords().empty() ? nullptr : &texturing,
                                      order.one_sided(triangles.size()), occluder_triangles.empty() ? nullptr : &occluders);
    if (!c.ok()) return core::make_error("frame " + std::to_string(s.frame) + ": " + c.error().to_string());
    s.hole_ratio = c->hole_ratio;
    s.thin_ratio = c->thin_ratio;
    s.iou = c->silhouette_iou;
    s.speck_ratio = c->speck_ratio;
    s.shading_error = c->shading_error;
    s.color_error = c->color_error;
    s.edge_excess = c->edge_excess;
    if (o.images_dir.empty()) return core::Status::success();
    char stem[64];
    std::snprintf(stem, sizeof stem, "/%s_f%04llu_", scene.name.c_str(), (unsigned long long)s.frame);
    PBDSPLAT_TRY(core::write_png(o.images_dir + stem + "splats.png", c->splats));
    PBDSPLAT_TRY(core::write_png(o.images_dir + stem + "mesh.png", c->shaded));
    core::ImageRgba8 marked;
    passes::speck_ratio(c->splats, c->shaded, c->mesh, &marked);
    return core::write_png(o.images_dir + stem + "specks.png", marked);
}

// The report's worst figures over its samples.
void summarise(CheckReport& report, std::vector<double> stage_a) {
    for (const CheckSample& s : report.samples) {
        report.shape_error_max = std::max(report.shape_error_max, s.shape_error);
        if (s.cuts == 0 && s.tears == 0) report.shape_error_before_topology = std::max(report.shape_error_before_topology, s.shape_error);
        report.strays_max = std::max(report.strays_max, s.strays);
        report.stretch_max = std::max(report.stretch_max, s.stretch);
        report.gaussians_max = std::max(report.gaussians_max, s.gaussians);
        report.volume_error_max = std::max(report.volume_error_max, s.volume_error);
        report.penetration_max = std::max(report.penetration_max, s.penetration);
        report.crossing_ratio_max = std::max(report.crossing_ratio_max, s.crossing_ratio);
        report.tilt_max = std::max(report.tilt_max, s.tilt_degrees);
        report.height_ratio_min = std::min(report.height_ratio_min, s.height_ratio);
        report.volume_ratio_min = std::min(report.volume_ratio_min, s.volume_ratio);
        if (s.smallest_piece_triangles > 0)
            report.smallest_piece_min = report.smallest_piece_min == 0 ? s.smallest_piece_triangles
                                                                       : std::min(report.smallest_piece_min, s.smallest_piece_triangles);
        if (s.hole_ratio >= 0.0) {
            report.hole_ratio_max = std::max(report.hole_ratio_max, s.hole_ratio);
            report.thin_ratio_max = std::max(report.thin_ratio_max, s.thin_ratio);
            report.iou_min = report.iou_min < 0.0 ? s.iou : std::min(report.iou_min, s.iou);
            report.speck_ratio_max = std::max(report.speck_ratio_max, s.speck_ratio);
            report.shading_error_max = std::max(report.shading_error_max, s.shading_error);
            report.color_error_max = std::max(report.color_error_max, s.color_error);
            report.edge_excess_max = std::max(report.edge_excess_max, s.edge_excess);
        }
        if (s.spacing_within >= 0.0) {
            report.spacing_within_min = report.spacing_within_min < 0.0 ? s.spacing_within : std::min(report.spacing_within_min, s.spacing_within);
            report.spacing_within_3d_min =
                report.spacing_within_3d_min < 0.0 ? s.spacing_within_3d : std::min(report.spacing_within_3d_min, s.spacing_within_3d);
        }
    }
    if (!report.samples.empty()) {
        report.pieces = report.samples.back().pieces;
        report.tears = report.samples.back().tears;
        report.particles = report.samples.back().particles;
        report.gaussians = report.samples.back().gaussians;
        report.speed_rms_end = report.samples.back().speed_rms;
    }
    if (!stage_a.empty()) {
        std::nth_element(stage_a.begin(), stage_a.begin() + long(stage_a.size() / 2), stage_a.end());
        report.stage_a_ms = stage_a[stage_a.size() / 2];
    }
}

// A burst's figures, read every frame from the first frame that tore, for 2 s.
class BurstWatch {
public:
    explicit BurstWatch(const sim::OpeningReport& at_load) : at_load_(at_load) {}
    void frame(const SceneRuntime& rt, const FrameStats& st, CheckReport& report) {
        if (st.tears == 0 || (start_ >= 0.0f && st.time > start_ + 2.0f)) return;
        const auto faces = [&rt](const std::vector<uint32_t>& loop) { return rt.cut_faces().triangles_of(loop); };
        const sim::OpeningReport opening = sim::opening_report(rt.body(), faces);
        // Openings made since load: the model's own holes are not a rip.
        const double opened = opening.open_length - at_load_.open_length;
        if (start_ < 0.0f) {
            start_ = st.time, open_length_ = opened, volume_ = opening.volume;
            report.rip_growth = 1.0;
            return;
        }
        if (open_length_ > 0.0) report.rip_growth = opened / open_length_;
        if (volume_ != 0.0) report.burst_volume_ratio = std::min(report.burst_volume_ratio, opening.volume / volume_);
    }

private:
    sim::OpeningReport at_load_;
    float start_ = -1.0f;
    double open_length_ = 0.0, volume_ = 0.0;
};

// How far a drag stretches what it holds before anything tears: the grabbed part (the model part
// of the held particle nearest the grab point) measured along the pull, whose way is known only
// once the grab has moved, so the part's particles are kept as they were when it began.
class PullWatch {
public:
    void frame(const SceneRuntime& rt, const FrameStats& st, CheckReport& report) {
        const sim::DragConstraint& drag = rt.drag();
        if (!drag.active || drag.particles.empty()) {
            started_ = false;
            return;
        }
        const sim::SoftBody& b = rt.body();
        if (!started_) {
            started_ = true, done_ = false;
            start_target_ = drag.target, tears_ = st.tears;
            const uint32_t held = drag.particles.front();
            const uint32_t part = held < b.part_of_particle.size() ? b.part_of_particle[held] : 0;
            particles_.clear(), start_.clear();
            for (uint32_t i = 0; i < b.particle_count(); ++i)
                if (b.part_of_particle.size() != b.particle_count() || b.part_of_particle[i] == part)
                    particles_.push_back(i), start_.push_back(sim::xyz(b.particles.x[i]));
            report.pull_stretch = std::max(report.pull_stretch, 1.0);
            return;
        }
        if (done_) return;
        // The frame that tore is measured before its tear moved anything apart.
        done_ = st.tears > tears_;
        const Vec3f way = drag.target - start_target_;
        if (way.squaredNorm() <= 0.0f) return;
        const Vec3f d = way.normalized();
        float lo0 = FLT_MAX, hi0 = -FLT_MAX, lo = FLT_MAX, hi = -FLT_MAX;
        for (size_t k = 0; k < particles_.size(); ++k) {
            const float s0 = start_[k].dot(d), s = sim::xyz(b.particles.x[particles_[k]]).dot(d);
            lo0 = std::min(lo0, s0), hi0 = std::max(hi0, s0), lo = std::min(lo, s), hi = std::max(hi, s);
        }
        if (hi0 > lo0) report.pull_stretch = std::max(report.pull_stretch, double(hi - lo) / double(hi0 - lo0));
    }

private:
    bool started_ = false, done_ = false;
    Vec3f start_target_ = Vec3f::Zero();
    size_t tears_ = 0;
    std::vector<uint32_t> particles_;
    std::vector<Vec3f> start_;
};

// The surface as the coverage images see it, before the first step: the area ratio's 1.
double rest_area_of(SceneRuntime& rt) {
    std::vector<Vec4f> x;
    std::vector<mesh::Triangle> triangles;
    rt.deformed_surface(x, triangles);
    return area_of(x, triangles);
}
} // namespace

core::Result<CheckReport> check_scene(const Scene& scene, const CheckOptions& o) {
    RuntimeOptions ro;  // simulation and mapping only: coverage renders its own pair of images
    ro.keep_records = true;
    // Every cut and tear checked against the invariants, where the mesh as loaded keeps them (a
    // model the repair could not make fully manifold is reported, and run unchecked).
    ro.check_topology = true;
    auto created = SceneRuntime::create(scene, ro);
    if (!created.ok()) return created.error();
    SceneRuntime& rt = *created.value();
    CheckReport report;
    report.invariants_at_load = rt.invariants_at_load();
    report.model_vertices = rt.decimation().input_vertices;
    report.simulation_particles = rt.body().particle_count();
    if (rt.fine_surface())
        report.embedding_error = rt.embedding().max_rest_error / std::max(mesh::bounds(*rt.fine_surface()).diagonal(), 1e-12f);
    std::vector<double> stage_a;
    const sim::OpeningReport at_load = sim::opening_report(rt.body());
    BurstWatch burst(at_load);
    PullWatch pull;
    const double rest_area = o.gpu ? rest_area_of(rt) : 0.0;
    for (uint32_t f = 0; f < o.frames; ++f) {
        PBDSPLAT_TRY(rt.step());
        const FrameStats& st = rt.stats();
        stage_a.push_back(st.groups.stage_a());
        burst.frame(rt, st, report);
        pull.frame(rt, st, report);
        if ((f + 1) % o.every != 0 && f + 1 != o.frames) continue;
        CheckSample s;
        s.frame = st.frame;
        s.time = st.time;
        s.cuts = st.cuts;
        s.tears = st.tears;
        s.particles = st.particles;
        s.gaussians = st.gaussians;
        sample_body_and_splats(rt, at_load.volume, s);
        if (o.gpu) PBDSPLAT_TRY(sample_coverage(rt, scene, o, rest_area, s));
        report.samples.push_back(s);
    }
    summarise(report, std::move(stage_a));
    // A pass that reached data it did not declare is a bug the graph's order and culling cannot
    // see: the check fails on it.
    if (!rt.graph().access_violations().empty())
        return core::make_error("frame graph: " + rt.graph().access_violations().front() + " (" +
                                std::to_string(rt.graph().access_violations().size()) + " undeclared accesses)");
    return report;
}

} // namespace pbdsplat::scene
