#pragma once
// Internal to the scene room: the plain keys of each scene-file section, described once. The
// reader (scene_file.cpp) and the writer (scene_toml.cpp) both walk these tables, so a key
// cannot be read and forgotten by the writer, or written with another name or range. Keys with
// more to them (enums, optional values, arrays, nested tables) are read and written by hand
// beside the tables.
#include <string>
#include <variant>

#include "scene/scene.h"

namespace pbdsplat::scene::keys {

// One key: its name, where the value lives in the section's struct, its range.
template <class D>
struct Key {
    using Real = float& (*)(D&);
    using Count = uint32_t& (*)(D&);
    using Flag = bool& (*)(D&);
    using Vec3 = Vec3f& (*)(D&);
    using Text = std::string& (*)(D&);
    using Scale = ModelScale& (*)(D&);  // a number, or an array of 3
    const char* name;
    std::variant<Real, Count, Flag, Vec3, Text, Scale> at;
    double lo = -1e6, hi = 1e6;
};
// `member` is an expression on `d`, the section's struct: KEY(SurfaceDesc, "eta", eta, 0.05, 4.0).
#define PBDSPLAT_KEY(D, name, member, ...) \
    Key<D> { name, +[](D& d) -> decltype(auto) { return (d.member); }, __VA_ARGS__ }

template <class... F>
struct Overloaded : F... {
    using F::operator()...;
};

inline const Key<ModelDesc> k_model_keys[] = {
    PBDSPLAT_KEY(ModelDesc, "mesh", mesh),
    PBDSPLAT_KEY(ModelDesc, "fit", fit, 0.0, 1e4),
    PBDSPLAT_KEY(ModelDesc, "translate", translate),
    PBDSPLAT_KEY(ModelDesc, "rotate_degrees", rotate_degrees, -3600, 3600),
    PBDSPLAT_KEY(ModelDesc, "scale", scale, 1e-6, 1e6),
    PBDSPLAT_KEY(ModelDesc, "close_holes", close_holes),
    PBDSPLAT_KEY(ModelDesc, "velocity", velocity, -1e4, 1e4),
    PBDSPLAT_KEY(ModelDesc, "static", fixed),
};
inline const Key<MaterialDesc> k_material_keys[] = {
    PBDSPLAT_KEY(MaterialDesc, "color", color, 0.0, 1.0),
    PBDSPLAT_KEY(MaterialDesc, "opacity", opacity, 1e-4, 0.9999),
    PBDSPLAT_KEY(MaterialDesc, "shininess", shininess, 1.0, 10000.0),
    PBDSPLAT_KEY(MaterialDesc, "diffuse", diffuse, 0.0, 10.0),
    PBDSPLAT_KEY(MaterialDesc, "specular", specular, 0.0, 10.0),
    PBDSPLAT_KEY(MaterialDesc, "splat_scale", splat_scale, 0.01, 10.0),
};
// After `mode`.
inline const Key<SurfaceDesc> k_surface_keys[] = {
    PBDSPLAT_KEY(SurfaceDesc, "eta", eta, 0.05, 4.0),
    PBDSPLAT_KEY(SurfaceDesc, "sample_budget", sample_budget, 0, 1u << 26),
    PBDSPLAT_KEY(SurfaceDesc, "stretch_scale", stretch_scale),
    PBDSPLAT_KEY(SurfaceDesc, "seed", seed, 0, 0x7fffffff),
    PBDSPLAT_KEY(SurfaceDesc, "edge_samples", edge_samples),
    PBDSPLAT_KEY(SurfaceDesc, "density", density.enabled),
};
// [advanced]: the density control's internals, each with a default chosen from measurements
// (docs/scene-format.md, "[advanced]"); no shipped scene sets them.
inline const Key<SurfaceDesc> k_advanced_keys[] = {
    PBDSPLAT_KEY(SurfaceDesc, "density_grow", density.grow, 1.05, 4.0),
    PBDSPLAT_KEY(SurfaceDesc, "density_shrink", density.shrink, 0.2, 0.95),
    PBDSPLAT_KEY(SurfaceDesc, "density_squash", density.squash, 0.2, 0.95),
    PBDSPLAT_KEY(SurfaceDesc, "density_retire_spacing", density.retire_spacing, 0.3, 1.0),
    PBDSPLAT_KEY(SurfaceDesc, "density_insert_spacing", density.insert_spacing, 0.3, 1.0),
    PBDSPLAT_KEY(SurfaceDesc, "density_settle_frames", density.settle_frames, 1, 60),
    PBDSPLAT_KEY(SurfaceDesc, "density_budget", density.budget, 1, 1u << 20),
    PBDSPLAT_KEY(SurfaceDesc, "density_crowd_spacing", density.crowd_spacing, 0.0, 0.95),
    PBDSPLAT_KEY(SurfaceDesc, "density_gap_spacing", density.gap_spacing, 0.0, 4.0),
};
// After `mode`; `particles`, `cut_volume`, the pins and the colliders beside it.
inline const Key<SimulationDesc> k_simulation_keys[] = {
    PBDSPLAT_KEY(SimulationDesc, "dt", dt, 1.0 / 1000.0, 1.0 / 10.0),
    PBDSPLAT_KEY(SimulationDesc, "iterations", solver.iterations, 1, 1000),
    PBDSPLAT_KEY(SimulationDesc, "substeps", solver.substeps, 1, 1000),
    PBDSPLAT_KEY(SimulationDesc, "stiffness", solver.stretch_stiffness, 1e-4, 1.0),
    PBDSPLAT_KEY(SimulationDesc, "compliance", compliance, 0.0, 1e3),
    PBDSPLAT_KEY(SimulationDesc, "volume", solver.volume),
    PBDSPLAT_KEY(SimulationDesc, "volume_stiffness", solver.volume_stiffness, 1e-4, 1.0),
    PBDSPLAT_KEY(SimulationDesc, "volume_compliance", volume_compliance, 0.0, 1e3),
    PBDSPLAT_KEY(SimulationDesc, "shape_stiffness", solver.shape_stiffness, 0.0, 1.0),
    PBDSPLAT_KEY(SimulationDesc, "shape_compliance", solver.shape_compliance, 0.0, 1e3),
    PBDSPLAT_KEY(SimulationDesc, "pressure", pressure, 0.01, 100.0),
    PBDSPLAT_KEY(SimulationDesc, "gravity", solver.gravity, -1000, 1000),
    PBDSPLAT_KEY(SimulationDesc, "damping", solver.damping, 0.0, 1000.0),
    PBDSPLAT_KEY(SimulationDesc, "deform_damping", solver.deform_damping, 0.0, 1000.0),
    PBDSPLAT_KEY(SimulationDesc, "mass", mass, 1e-6, 1e6),
    PBDSPLAT_KEY(SimulationDesc, "friction", friction, 0.0, 10.0),
    PBDSPLAT_KEY(SimulationDesc, "static_friction", static_friction, 0.0, 10.0),
    PBDSPLAT_KEY(SimulationDesc, "contact", solver.contact.enabled),
    PBDSPLAT_KEY(SimulationDesc, "contact_thickness", solver.contact.thickness, 0.0, 10.0),
    PBDSPLAT_KEY(SimulationDesc, "self_contact", solver.contact.self),
    PBDSPLAT_KEY(SimulationDesc, "fold_guard", solver.contact.folds),
    PBDSPLAT_KEY(SimulationDesc, "fold_edges", solver.contact.fold_edges),
    PBDSPLAT_KEY(SimulationDesc, "contact_substeps", solver.contact.substeps, 1, 64),
    PBDSPLAT_KEY(SimulationDesc, "sleep", solver.sleep.enabled),
    PBDSPLAT_KEY(SimulationDesc, "weld_parts", weld_parts),
    PBDSPLAT_KEY(SimulationDesc, "cut_snap", cut.snap, 0.0, 0.45),
    PBDSPLAT_KEY(SimulationDesc, "fade_frames", fade_frames, 1, 600),
};

// After `blend`, `sort_on`, `shading`, `footprint`, `carrier` and `splat_shape`.
inline const Key<RenderDesc> k_render_keys[] = {
    PBDSPLAT_KEY(RenderDesc, "width", width, 16, 16384),
    PBDSPLAT_KEY(RenderDesc, "height", height, 16, 16384),
    PBDSPLAT_KEY(RenderDesc, "sort", sort),
    PBDSPLAT_KEY(RenderDesc, "surfel_thickness", surfel_thickness, 0.01, 1.0),
    PBDSPLAT_KEY(RenderDesc, "occluder_tolerance", occluder_tolerance, 0.05, 20.0),
    PBDSPLAT_KEY(RenderDesc, "ground", ground),
    PBDSPLAT_KEY(RenderDesc, "cull_back", cull_back),
    PBDSPLAT_KEY(RenderDesc, "kappa", frame.style.kappa, 0.0, 6.0),
    PBDSPLAT_KEY(RenderDesc, "thin_below", frame.style.thin_below, 0.0, 16.0),
    PBDSPLAT_KEY(RenderDesc, "depth_min_alpha", frame.style.depth_min_alpha, 0.0, 0.99),
    PBDSPLAT_KEY(RenderDesc, "depth_push", frame.style.depth_push, 0.0, 10.0),
    PBDSPLAT_KEY(RenderDesc, "environment_intensity", frame.lighting.environment.intensity, 0.0, 100.0),
    PBDSPLAT_KEY(RenderDesc, "environment_diffuse", frame.lighting.environment.diffuse, 0.0, 100.0),
    PBDSPLAT_KEY(RenderDesc, "environment_specular", frame.lighting.environment.specular, 0.0, 100.0),
};
// [render.camera], before `orbit_degrees_per_second` and `path`.
inline const Key<render::Camera> k_camera_keys[] = {
    PBDSPLAT_KEY(render::Camera, "eye", eye),
    PBDSPLAT_KEY(render::Camera, "target", target),
    PBDSPLAT_KEY(render::Camera, "up", up),
    PBDSPLAT_KEY(render::Camera, "fov_degrees", fov_y_degrees, 1.0, 170.0),
};
// [render.light]: the key light.
inline const Key<render::Lighting> k_key_light_keys[] = {
    PBDSPLAT_KEY(render::Lighting, "direction", direction),  // normalised where it is used
    PBDSPLAT_KEY(render::Lighting, "color", color, 0.0, 100.0),
    PBDSPLAT_KEY(render::Lighting, "intensity", intensity, 0.0, 100.0),
    PBDSPLAT_KEY(render::Lighting, "ambient", ambient, 0.0, 100.0),
};
// One entry of render.lights, after `type`.
inline const Key<render::Light> k_light_keys[] = {
    PBDSPLAT_KEY(render::Light, "position", position),
    PBDSPLAT_KEY(render::Light, "direction", direction),
    PBDSPLAT_KEY(render::Light, "color", color, 0.0, 100.0),
    PBDSPLAT_KEY(render::Light, "intensity", intensity, 0.0, 1000.0),
    PBDSPLAT_KEY(render::Light, "range", range, 1e-3, 1e6),
    PBDSPLAT_KEY(render::Light, "inner_degrees", inner_degrees, 0.0, 89.0),
    PBDSPLAT_KEY(render::Light, "outer_degrees", outer_degrees, 0.1, 89.9),
};

#undef PBDSPLAT_KEY

} // namespace pbdsplat::scene::keys
