#include "scene/scene_model.h"

#include <filesystem>

#include "mesh/mesh_spec.h"

namespace pbdsplat::scene {

uint32_t simulation_particles(const Scene& scene) {
    if (scene.simulation.particles) return *scene.simulation.particles;
    return mesh::is_procedural_spec(scene.model.mesh) ? 0u : k_default_simulation_particles;
}

core::Result<SceneModel> load_scene_model(const Scene& scene) {
    mesh::MeshSpecOptions mo;
    mo.file_fit_diagonal = scene.model.fit;
    mo.close_holes = scene.model.close_holes;
    std::string spec = scene.model.mesh;
    // A model file is looked up next to the scene first.
    if (!scene.source_dir.empty()) {
        const std::filesystem::path beside = std::filesystem::path(scene.source_dir) / spec;
        std::error_code ec;
        if (std::filesystem::is_regular_file(beside, ec)) spec = beside.string();
    }
    auto repaired = mesh::load_mesh_spec(spec, mo);
    if (!repaired.ok()) return repaired.error();
    mesh::TriangleMesh m = std::move(repaired).value().mesh;
    const ModelDesc& md = scene.model;
    const Mat3f r = (Eigen::AngleAxisf(math::radians(md.rotate_degrees.z()), Vec3f::UnitZ()) *
                     Eigen::AngleAxisf(math::radians(md.rotate_degrees.y()), Vec3f::UnitY()) *
                     Eigen::AngleAxisf(math::radians(md.rotate_degrees.x()), Vec3f::UnitX()))
                        .toRotationMatrix();
    for (Vec3f& p : m.positions) p = r * (p * md.scale) + md.translate;

    SceneModel out;
    const uint32_t target = simulation_particles(scene);
    mesh::TriangleMesh coarse;
    if (target > 0 && target < m.vertex_count()) {
        mesh::DecimateOptions d;
        d.target_vertices = target;
        auto dec = mesh::decimate(m, d, scene.model.mesh);
        if (!dec.ok()) return dec.error();
        coarse = std::move(dec.value().mesh);
        out.decimation = dec.value().report;
        out.fine = std::move(m);
    } else {
        if (target > 0 && target < 4)
            return core::make_error("simulation.particles = " + std::to_string(target) + ": a body needs at least 4 (0 keeps the model's)");
        out.decimation.input_vertices = out.decimation.output_vertices = m.vertex_count();
        out.decimation.input_triangles = out.decimation.output_triangles = m.triangle_count();
        coarse = std::move(m);
    }

    const SimulationDesc& s = scene.simulation;
    sim::SoftBodyDesc desc;
    desc.total_mass = s.mass;
    desc.stretch_compliance = s.compliance;
    desc.volume = s.solver.volume;
    desc.pressure = s.pressure;
    desc.volume_compliance = s.volume_compliance;
    desc.shape_matching = s.solver.shape_stiffness > 0.0f;
    auto body = sim::make_soft_body(std::move(coarse), desc);
    if (!body.ok()) return body.error();
    sim::SoftBody b = std::move(body).value();
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
    if (!s.pins.empty() || !s.pin_regions.empty()) sim::rebuild_shape_clusters(b);
    out.body = std::move(b);
    return out;
}

core::Result<sim::SoftBody> make_scene_body(const Scene& scene) {
    auto m = load_scene_model(scene);
    if (!m.ok()) return m.error();
    return std::move(m.value().body);
}

} // namespace pbdsplat::scene
