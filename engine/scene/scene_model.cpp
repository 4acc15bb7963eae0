#include "scene/scene_model.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <limits>
#include <string>
#include <utility>

#include "asset/mesh_spec.h"
#include "mesh/reorder.h"
#include "mesh/subdivide.h"
#include "sim/contact.h"
#include "sim/crossings.h"
#include "sim/solver.h"
#include "sim/weld.h"

namespace pbdsplat::scene {

uint32_t simulation_particles(const Scene& scene) {
    if (scene.model_own.particles) return *scene.model_own.particles;
    if (scene.simulation.particles) return *scene.simulation.particles;
    return asset::is_procedural_spec(scene.model.mesh) ? 0u : k_default_simulation_particles;
}

namespace {

// One model of the scene as the simulation takes it: its simulation mesh (Morton-ordered, so
// the parts of a scene sit in index ranges of their own), and the model's own surface when the
// simulation mesh is a decimated copy of it.
struct Part {
    mesh::TriangleMesh coarse;
    std::optional<mesh::TriangleMesh> fine;
    mesh::DecimateReport decimation;
    std::optional<asset::SurfaceLook> look;  // in scene coordinates
};

core::Result<Part> load_part(const ModelDesc& md, uint32_t target, const std::string& source_dir) {
    asset::MeshSpecOptions mo;
    mo.file_fit_diagonal = md.fit;
    mo.close_holes = md.close_holes;
    mo.up = md.up;
    std::string spec = md.mesh;
    // A model file is looked up next to the scene first.
    if (!source_dir.empty()) {
        const std::filesystem::path beside = std::filesystem::path(source_dir) / spec;
        std::error_code ec;
        if (std::filesystem::is_regular_file(beside, ec)) spec = beside.string();
    }
    auto loaded = asset::load_model(spec, mo);
    if (!loaded.ok()) return loaded.error();
    for (const std::string& w : loaded.value().warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    mesh::TriangleMesh m = std::move(loaded.value().repaired.mesh);
    if (asset::is_procedural_spec(md.mesh)) mesh::refine_to(m, asset::k_min_procedural_vertices);
    const Mat3f r = (Eigen::AngleAxisf(math::radians(md.rotate_degrees.z()), Vec3f::UnitZ()) *
                     Eigen::AngleAxisf(math::radians(md.rotate_degrees.y()), Vec3f::UnitY()) *
                     Eigen::AngleAxisf(math::radians(md.rotate_degrees.x()), Vec3f::UnitX()))
                        .toRotationMatrix();
    // The surface and the look it is painted from move together.
    const auto place = [&](std::vector<Vec3f>& positions) {
        for (Vec3f& p : positions) p = r * p.cwiseProduct(md.scale.axes) + md.translate;
    };
    place(m.positions);
    Part out;
    out.look = std::move(loaded.value().look);
    if (out.look) place(out.look->positions);
    if (target > 0 && target < m.vertex_count()) {
        mesh::DecimateOptions d;
        d.target_vertices = target;
        auto dec = mesh::decimate(m, d, md.mesh);
        if (!dec.ok()) return dec.error();
        out.coarse = std::move(dec.value().mesh);
        out.decimation = dec.value().report;
        out.fine = std::move(m);
    } else {
        if (target > 0 && target < 4)
            return core::make_error("simulation.particles = " + std::to_string(target) + ": a body needs at least 4 (0 keeps the model's)");
        out.decimation.input_vertices = out.decimation.output_vertices = m.vertex_count();
        out.decimation.input_triangles = out.decimation.output_triangles = m.triangle_count();
        out.coarse = std::move(m);
    }
    return out;
}

uint32_t part_particles(const ModelDesc& md, const std::optional<uint32_t>& asked) {
    if (asked) return *asked;
    return asset::is_procedural_spec(md.mesh) ? 0u : k_default_simulation_particles;
}



// Several models: the parts of one body, each in its own range of particles, laid end to end
// into `coarse` (and the fine surfaces into out.fine where any part has one).
core::Status merge_parts(const Scene& scene, Part first, mesh::TriangleMesh& coarse, SceneModel& out,
                         const std::function<void(std::optional<asset::SurfaceLook>&, const Vec3f&)>& add_look) {
    std::vector<Part> parts;
    parts.push_back(std::move(first));
    for (size_t k = 0; k < scene.bodies.size(); ++k) {
        const BodyDesc& b = scene.bodies[k];
        auto part = load_part(b.model, part_particles(b.model, b.own.particles), scene.source_dir);
        if (!part.ok()) return core::make_error(model_name(scene, k + 1) + ": " + part.error().to_string());
        add_look(part.value().look, b.own.color.value_or(scene.material.color));
        parts.push_back(std::move(part).value());
    }
    bool any_fine = false, any_color = scene.model_own.color.has_value();
    for (const Part& p : parts) any_fine = any_fine || p.fine.has_value();
    for (const BodyDesc& b : scene.bodies) any_color = any_color || b.own.color.has_value();
    mesh::TriangleMesh fine;
    for (size_t k = 0; k < parts.size(); ++k) {
        Part& p = parts[k];
        const Vec3f color = own_settings(scene, k).color.value_or(scene.material.color);
        if (any_color) {
            p.coarse.colors.assign(p.coarse.vertex_count(), color);
            if (p.fine) p.fine->colors.assign(p.fine->vertex_count(), color);
        }
        mesh::reorder_for_locality(p.coarse);
        out.part_start.push_back(uint32_t(coarse.vertex_count()));
        if (any_fine) {
            const uint32_t first_triangle = uint32_t(fine.triangle_count());
            mesh::append(fine, p.fine ? *p.fine : p.coarse, Eigen::Affine3f::Identity(), color);
            if (!p.fine) out.fine_copies.triangles.emplace_back(first_triangle, uint32_t(fine.triangle_count()));
            out.fine_copies.model.push_back(p.fine ? 0 : 1);
        }
        mesh::append(coarse, p.coarse, Eigen::Affine3f::Identity(), color);
        out.decimation.input_vertices += p.decimation.input_vertices;
        out.decimation.output_vertices += p.decimation.output_vertices;
        out.decimation.input_triangles += p.decimation.input_triangles;
        out.decimation.output_triangles += p.decimation.output_triangles;
    }
    out.part_start.push_back(uint32_t(coarse.vertex_count()));
    if (any_fine) out.fine = std::move(fine);
    return core::Status::success();
}

core::Result<sim::SoftBody> make_body(const Scene& scene, mesh::TriangleMesh coarse) {
    const SimulationDesc& s = scene.simulation;
    sim::SoftBodyDesc desc;
    desc.total_mass = s.mass;
    desc.stretch_compliance = s.compliance;
    desc.volume = s.solver.volume;
    desc.pressure = s.pressure;
    desc.volume_compliance = s.volume_compliance;
    desc.shape_matching = stiffest_shape(scene) > 0.0f;
    desc.reorder = scene.bodies.empty();  // the parts were ordered one by one, and keep their ranges
    return sim::make_soft_body(std::move(coarse), desc);
}

// Model m's particles, [first, last): a scene of one model lays no parts end to end, so it is
// every particle.
std::pair<uint32_t, uint32_t> model_range(const std::vector<uint32_t>& part_start, size_t m, const sim::SoftBody& b) {
    if (part_start.empty()) return {0u, uint32_t(b.particle_count())};
    return {part_start[m], part_start[m + 1]};
}

// A model's own `mass`: its particles' masses scaled to that total, each keeping its share by
// area. Returns whether any changed (the shape clusters weigh their fits by them).
bool weigh_models(const Scene& scene, const std::vector<uint32_t>& part_start, sim::SoftBody& b) {
    bool changed = false;
    for (size_t m = 0; m <= scene.bodies.size(); ++m) {
        const std::optional<float>& mass = own_settings(scene, m).mass;
        if (!mass) continue;
        const auto [begin, end] = model_range(part_start, m, b);
        double now = 0.0;
        for (uint32_t i = begin; i < end; ++i) now += 1.0 / double(b.particles.w[i]);
        const double factor = now / double(*mass);  // on the inverse masses
        for (uint32_t i = begin; i < end; ++i) b.particles.w[i] = float(double(b.particles.w[i]) * factor);
        changed = true;
    }
    return changed;
}

// Each model's particles, so that contact tells two models apart from two parts of one; the
// [[bodies]] held still or thrown; the stiffnesses and dampings of those that name their own.
void place_bodies(const Scene& scene, const std::vector<uint32_t>& part_start, sim::SoftBody& b) {
    b.model_of_particle.assign(b.particle_count(), 0);
    const size_t models = scene.bodies.size() + 1;
    b.model_shape_stiffness.clear(), b.model_damping.clear(), b.model_deform_damping.clear(), b.model_stretch_stiffness.clear();
    const auto set = [&](std::vector<float>& per_model, size_t m, const std::optional<float>& own) {
        if (own) per_model.resize(models, -1.0f), per_model[m] = *own;
    };
    for (size_t m = 0; m < models; ++m) {
        const OwnSettings& own = own_settings(scene, m);
        set(b.model_shape_stiffness, m, own.shape_stiffness), set(b.model_damping, m, own.damping);
        set(b.model_deform_damping, m, own.deform_damping), set(b.model_stretch_stiffness, m, own.stiffness);
    }
    for (size_t m = 0; m <= scene.bodies.size(); ++m) {
        const ModelDesc& d = m == 0 ? scene.model : scene.bodies[m - 1].model;
        const auto [begin, end] = model_range(part_start, m, b);
        for (uint32_t i = begin; i < end; ++i) {
            b.model_of_particle[i] = uint32_t(m);
            if (d.fixed) b.pin(i);
            else b.particles.v[i] = sim::to4(d.velocity);
        }
    }
}

// Each model's own XPBD stretch compliance, on its edges (a cut's new edges take their parent's).
void set_model_compliances(const Scene& scene, sim::SoftBody& b) {
    for (sim::DistanceConstraint& c : b.distance)
        if (const std::optional<float>& own = own_settings(scene, b.model_of_particle[c.i]).compliance) c.compliance = *own;
}

// Each model's own pressure factor: a balloon blown up beside solids at their own volume.
void set_model_pressures(const Scene& scene, sim::SoftBody& b) {
    const std::vector<uint32_t> model_of_piece = b.model_of_pieces();
    for (sim::VolumeConstraint& v : b.volumes) v.pressure = pressure_of(scene, model_of_piece[v.piece]);
}

// Two models placed into each other stay so (contact leaves alone what lay inside another at
// load, which is how a model's own parts are made): said, since it is almost always a slip.

void warn_crossing_models(const Scene& scene, const sim::SoftBody& b) {
    if (scene.bodies.empty()) return;
    const auto name = [&](uint32_t m) { return model_name(scene, m); };
    for (const sim::ModelOverlap& o : sim::models_crossing_at_rest(b))
        std::fprintf(stderr, "warning: scene '%s': %s and %s are placed into each other (%zu triangle pairs cross); contact keeps them so: move them apart\n",
                     scene.name.c_str(), name(o.a).c_str(), name(o.b).c_str(), o.pairs);
}

// A model placed partly below the ground plane is pushed out of it on the first step, and leaps.
void warn_below_ground(const Scene& scene, const sim::SoftBody& b) {
    const std::optional<sim::GroundPlane>& ground = scene.simulation.colliders.ground;
    if (!ground || b.particle_count() == 0) return;
    const size_t models = scene.bodies.size() + 1;
    std::vector<float> lowest(models, std::numeric_limits<float>::infinity());
    std::vector<Eigen::AlignedBox3f> box(models);
    for (size_t i = 0; i < b.particle_count(); ++i) {
        const uint32_t m = i < b.model_of_particle.size() ? std::min<uint32_t>(b.model_of_particle[i], uint32_t(models - 1)) : 0u;
        const Vec3f x = sim::xyz(b.particles.x[i]);
        lowest[m] = std::min(lowest[m], ground->normal.dot(x) - ground->offset);
        box[m].extend(x);
    }
    for (size_t m = 0; m < models; ++m) {
        // Deeper than a thousandth of the model's size: not the rounding of a model set on the ground.
        if (box[m].isEmpty() || !(lowest[m] < -1e-3f * box[m].diagonal().norm())) continue;
        std::fprintf(stderr, "warning: scene '%s': %s starts %.3g below the ground plane; the ground pushes it out on the first step and it leaps: raise it\n",
                     scene.name.c_str(), model_name(scene, m).c_str(), double(-lowest[m]));
    }
}

// A step in which gravity alone moves a particle by more than half an edge outruns what the
// constraints and the contacts can hold in a few iterations: the skin tears into sheets and
// strays (dt 0.1 s under 1000 m/s^2 moved the bunny 10 m a step). Said, with the substeps that
// would do.
void warn_coarse_step(const Scene& scene, const sim::SoftBody& b, uint32_t substeps) {
    const sim::SolverSettings& s = scene.simulation.solver;
    const float edge = sim::mean_rest_edge(b), g = s.gravity.norm();
    const float h = scene.simulation.dt / float(std::max(1u, substeps));
    if (!(edge > 0.0f) || !(g * h * h > 0.5f * edge)) return;
    const double enough = std::ceil(double(scene.simulation.dt) * std::sqrt(double(g) / (0.5 * double(edge))));
    std::fprintf(stderr,
                 "warning: scene '%s': gravity moves a particle %.3g a step (dt / substeps = %.3g s), %.3g times the mean edge: the "
                 "body cannot hold its shape; set [simulation] substeps to %.0f or more\n",
                 scene.name.c_str(), double(g * h * h), double(h), double(g * h * h / edge), enough);
}

// The smallest mean rest edge of a model that can move (not fixed), or 0 where none can.
float smallest_moving_edge(const Scene& scene, const sim::SoftBody& b) {
    const std::vector<float> edges = sim::mean_rest_edge_of_models(b);
    float least = 0.0f;
    for (size_t m = 0; m < edges.size(); ++m) {
        const bool fixed = m == 0 ? scene.model.fixed : m - 1 < scene.bodies.size() && scene.bodies[m - 1].model.fixed;
        if (!fixed && edges[m] > 0.0f && (least == 0.0f || edges[m] < least)) least = edges[m];
    }
    return least;
}

// A solid stands on what holds it up while gravity's share of a frame, g dt^2 / substeps, stays
// near a tenth of its mean edge. Linear in the substeps, not quadratic: shape matching's
// stiffness is a share of a frame (spread over its iterations and substeps), so what a frame
// leaves of the sag is its substeps' g (dt / n)^2 summed, and the body tips by it frame after
// frame. Measured on the bunny dropped a quarter of its size (docs/BENCHMARKS.md, "Solids that
// stand"): fitted to 0.2 m it stands at 5 substeps (0.11 edges) and tips at 4 (0.14) and 3; to
// 2 cm at 48 (0.11) and not at 32 (0.17); at the 2 m the defaults are tuned at, 0.05 at one.
constexpr double k_standing_share = 0.1;

// `share`: gravity's step over a frame at one substep, g dt^2, over the solid's mean edge.
uint32_t standing_substeps(const Scene& scene, double share) {
    const SimulationDesc& sim = scene.simulation;
    const sim::Colliders& c = sim.colliders;
    const bool held_up = c.ground.has_value() || !c.spheres.empty() || !c.boxes.empty() || !scene.bodies.empty();
    if (!(stiffest_shape(scene) > 0.0f) || !held_up || !(share > 0.0) || !std::isfinite(share)) return 1;
    return uint32_t(std::min(1e6, std::ceil(share / k_standing_share)));
}

// The substeps a frame takes: the scene's, or, where the file left them out, as many as let its
// smallest solid stand (said, as they cost Stage A in proportion), within the sweeps a frame may take.
uint32_t choose_substeps(const Scene& scene, const sim::SoftBody& b) {
    const sim::SolverSettings& s = scene.simulation.solver;
    const float edge = smallest_moving_edge(scene, b);
    const double dt = scene.simulation.dt;
    const double share = edge > 0.0f ? double(s.gravity.norm()) * dt * dt / double(edge) : 0.0;
    const uint32_t need = standing_substeps(scene, share), have = std::max(1u, s.substeps);
    if (need <= have) return have;
    if (scene.simulation.substeps_given) {
        std::fprintf(stderr,
                     "note: scene '%s': gravity moves a particle %.2g times the smallest model's mean edge a frame: a solid this small "
                     "may not stand; [simulation] substeps = %u lets it\n",
                     scene.name.c_str(), share, need);
        return have;
    }
    const uint32_t room = std::max(1u, sim::k_max_sweeps / std::max(1u, s.iterations));
    const uint32_t n = std::min(need, room);
    std::fprintf(stderr,
                 "note: scene '%s': gravity moves a particle %.2g times the smallest model's mean edge a frame; it steps in %u "
                 "substeps so that a solid this small stands (set [simulation] substeps to choose)%s\n",
                 scene.name.c_str(), share, n,
                 n < need ? (": it would take " + std::to_string(need) + ", more than a frame's sweeps allow").c_str() : "");
    return n;
}

core::Status pin_particles(const Scene& scene, sim::SoftBody& b) {
    const SimulationDesc& s = scene.simulation;
    for (uint32_t pin : s.pins) {
        if (pin >= b.particle_count())
            return core::make_error("pinned particle " + std::to_string(pin) + " does not exist: the mesh has " +
                                    std::to_string(b.particle_count()) + " particles");
        b.pin(pin);
    }
    for (const PinRegion& region : s.pin_regions)
        for (uint32_t i = 0; i < b.particle_count(); ++i) {
            const Vec3f x = sim::xyz(b.particles.x[i]);
            if ((x.array() >= region.min.array()).all() && (x.array() <= region.max.array()).all()) b.pin(i);
        }
    // Pins change the masses the shape clusters weigh the fit with.
    const bool any_fixed = scene.model.fixed || std::any_of(scene.bodies.begin(), scene.bodies.end(), [](const BodyDesc& d) { return d.model.fixed; });
    if (!s.pins.empty() || !s.pin_regions.empty() || any_fixed) sim::rebuild_shape_clusters(b);
    return core::Status::success();
}

} // namespace

core::Result<SceneModel> load_scene_model(const Scene& scene) {
    auto first = load_part(scene.model, simulation_particles(scene), scene.source_dir);
    if (!first.ok() && (scene.model_from_bodies || !scene.bodies.empty()))
        return core::make_error(model_name(scene, 0) + ": " + first.error().to_string());
    if (!first.ok()) return first.error();
    SceneModel out;
    auto add_look = [&](std::optional<asset::SurfaceLook>& look, const Vec3f& plain) {
        out.paint.model.push_back(look ? std::make_shared<const asset::SurfaceColors>(std::move(*look)) : nullptr);
        out.paint.plain.push_back(plain);
    };
    add_look(first.value().look, scene.model_own.color.value_or(scene.material.color));
    mesh::TriangleMesh coarse;
    if (scene.bodies.empty()) {
        coarse = std::move(first.value().coarse);
        out.fine = std::move(first.value().fine);
        out.decimation = first.value().decimation;
    } else {
        PBDSPLAT_TRY(merge_parts(scene, std::move(first).value(), coarse, out, add_look));
    }
    auto body = make_body(scene, std::move(coarse));
    if (!body.ok()) return body.error();
    sim::SoftBody b = std::move(body).value();
    if (weigh_models(scene, out.part_start, b)) sim::rebuild_shape_clusters(b);
    place_bodies(scene, out.part_start, b);
    set_model_pressures(scene, b);
    set_model_compliances(scene, b);
    if (!b.model_shape_stiffness.empty()) sim::rebuild_shape_clusters(b);
    warn_crossing_models(scene, b);
    warn_below_ground(scene, b);
    out.substeps = choose_substeps(scene, b);
    warn_coarse_step(scene, b, out.substeps);
    // A model's parts that touch at rest (a teapot's spout on its body) hold together: within an
    // edge of each other, the decimated surfaces' vertices no longer coincide where they met.
    // Welded parts are one object to shape matching too (sim/shape.h). The closed parts of a body
    // that keeps a shape are welded as well (a table's legs to its top, stiff or wobbly); a
    // balloon's (no shape matching) are not: its eyes would tear the skin as it deflates.
    const sim::WeldFrom from = stiffest_shape(scene) > 0.0f ? sim::WeldFrom::open_edges_and_closed_parts
                                                                              : sim::WeldFrom::open_edges;
    if (scene.simulation.weld_parts && sim::weld_touching_parts(b, sim::mean_rest_edge_of_models(b), from) > 0)
        sim::rebuild_shape_clusters(b);
    if (!out.paint.empty()) paint_particles(out.paint, b);
    PBDSPLAT_TRY(pin_particles(scene, b));
    out.body = std::move(b);
    return out;
}

core::Result<sim::SoftBody> make_scene_body(const Scene& scene) {
    auto m = load_scene_model(scene);
    if (!m.ok()) return m.error();
    return std::move(m.value().body);
}

std::string model_name(const Scene& scene, size_t m) {
    // As the file numbers its [[bodies]] entries, the first of them where it has no [model].
    const size_t entry = scene.model_from_bodies ? m : m - 1;
    const std::string& mesh = m == 0 ? scene.model.mesh : scene.bodies[m - 1].model.mesh;
    return m == 0 && !scene.model_from_bodies ? "[model] (" + mesh + ")" : "bodies[" + std::to_string(entry) + "] (" + mesh + ")";
}

} // namespace pbdsplat::scene
