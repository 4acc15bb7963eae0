#pragma once
// A scene: the model and its material, the simulation settings, the rendering settings and a
// timeline of events. Read from TOML files (docs/scene-format.md) or built in code.
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "asset/mesh_spec.h"
#include "core/names.h"
#include "core/math.h"
#include "render/frame_inputs.h"
#include "render/splat_pass.h"
#include "sim/colliders.h"
#include "sim/solver.h"
#include "surface/density.h"
#include "topology/cut.h"

namespace pbdsplat::scene {

// A model's scale: one factor, or one per axis (a box flattened into a table top). Applied in
// the model's own axes, before its rotation.
struct ModelScale {
    Vec3f axes = Vec3f::Ones();
    bool uniform() const { return axes.x() == axes.y() && axes.y() == axes.z(); }
    bool operator==(const ModelScale&) const = default;
};

struct ModelDesc {
    std::string mesh = "icosphere:4";  // procedural spec or OBJ path (see asset/mesh_spec.h)
    float fit = 2.0f;                  // files: bounding-box diagonal after loading; 0 keeps
    Vec3f translate = Vec3f::Zero();
    Vec3f rotate_degrees = Vec3f::Zero();  // applied x, then y, then z
    ModelScale scale;
    bool close_holes = false;  // cap the model's open boundary loops (a balloon needs a closed surface)
    asset::UpAxis up = asset::UpAxis::file_default;  // files: which axis is up in the file (z for STL)
    Vec3f velocity = Vec3f::Zero();  // m/s at the start
    bool fixed = false;              // static: every particle pinned (a table, a bowl, a ramp)
};

// What a model may set for itself, in [model] or a [[bodies]] entry; each unset one is the
// scene's.
struct OwnSettings {
    std::optional<Vec3f> color;            // linear rgb; the material's colour without it
    std::optional<uint32_t> particles;     // its simulation size; else simulation.particles
    std::optional<float> mass;             // kg, its own total; else its area's share of simulation.mass
    std::optional<float> shape_stiffness;  // else simulation.shape_stiffness
    std::optional<float> damping;          // 1/s, its velocity's decay; else simulation.damping
    std::optional<float> deform_damping;   // 1/s, its wobble's decay; else simulation.deform_damping
    std::optional<float> pressure;         // its pieces' pressure factor k; else simulation.pressure
    std::optional<float> stiffness;        // its PBD stretch stiffness; else simulation.stiffness
    std::optional<float> compliance;       // its XPBD stretch compliance (m/N); else simulation.compliance
};

// Another model beside [model] ([[bodies]] in a scene file): the pieces of one soft body, so
// every stage (sampling, density, mapping, cuts, tears, contact, checks, export) takes them as
// it takes the pieces of a cut. The simulation settings are the scene's but for its own.
struct BodyDesc {
    ModelDesc model;
    OwnSettings own;
};

enum class SurfaceMode { boundary, vertices };
inline constexpr core::EnumName<SurfaceMode> k_surface_mode_names[] = {{SurfaceMode::boundary, "boundary"}, {SurfaceMode::vertices, "vertices"}};

// Twice the bunny's 69,000 samples. A detailed scan sampled at its own edge takes as many splats
// as it has triangles: a 524,288-triangle sphere took 568,185 and 17.1 s to its first frame (the
// Intel VM; sampling half of it), and the surface's update grows with every splat. Within the
// budget: 149,465 splats, 7.9-8.2 s (the rest mostly the repair and decimation of the file).
inline constexpr uint32_t k_default_sample_budget = 150000;

struct SurfaceDesc {
    SurfaceMode mode = SurfaceMode::boundary;  // boundary particles, or mesh vertices only (Fig. 14a)
    float eta = 0.5f;            // h = eta * mean edge length; in vertices mode it sizes the splats alike
    // Boundary particles the first sampling places at most (about): h grows past eta times the
    // edge where the model's detail would take more (surface::spacing_for_budget). 0: no budget.
    uint32_t sample_budget = k_default_sample_budget;
    bool stretch_scale = false;  // grow splats with the stretch of their triangle
    uint32_t seed = 1;           // sampling seed
    bool edge_samples = true;    // small samples every h/2 along open boundaries (cuts, tears, rims)
    // Boundary particles kept at the sampling density every frame (fades: simulation.fade_frames).
    surface::DensityOptions density;
};

struct MaterialDesc {
    Vec3f color{0.85f, 0.32f, 0.25f};  // linear rgb
    float opacity = 0.98f;             // sigmoid(o) of every splat, in (0, 1)
    float shininess = 48.0f;
    float diffuse = 1.0f;   // weight of the light's diffuse term
    float specular = 0.35f;
    float splat_scale = 0.7f;  // splat std dev, in units of the sampling spacing h
    // The inside of the surface, seen through a cut or a tear (an opened shell), drawn in this
    // colour (linear rgb) instead of the outside's: flesh under a skin. Empty: the outside's.
    std::optional<Vec3f> interior_color;
};

struct PinRegion {
    Vec3f min, max;  // particles inside this box (world space, after the transform) are pinned
};

// A model file's simulation mesh, when the scene does not say: enough particles for the
// physics of a whole body, few enough that Stage A stays well under a millisecond or two.
inline constexpr uint32_t k_default_simulation_particles = 2000;
// Shape matching on by default: a body resting on the ground keeps its shape and stands on thin
// legs (at 0.3 a quadruped's legs fold on landing: docs/BENCHMARKS.md, "Solids that stand").
inline constexpr float k_default_shape_stiffness = 0.9f;

inline sim::SolverSettings default_scene_solver() {
    sim::SolverSettings s;
    s.shape_stiffness = k_default_shape_stiffness;
    return s;
}

struct SimulationDesc {
    sim::SolverSettings solver = default_scene_solver();
    // Whether the scene file set `substeps`. Where it did not, loading raises them for a solid
    // too small to stand at one (load_scene_model, SceneModel::substeps).
    bool substeps_given = false;
    // Particles of the simulation mesh (quadric decimation of the model); the model's own
    // surface rides on it as embedded samples. Empty: model files are decimated to
    // k_default_simulation_particles, procedural meshes keep theirs. 0: the model's vertices.
    std::optional<uint32_t> particles;
    float dt = 1.0f / 60.0f;
    float mass = 1.0f;
    float compliance = 0.0f;         // XPBD stretch compliance, m/N
    float volume_compliance = 0.0f;  // XPBD
    float pressure = 1.0f;           // initial k
    bool weld_parts = true;          // hold together the parts of a model that touch at rest (sim/weld.h)
    float friction = 0.4f;           // kinetic, of every contact (colliders and moving surfaces)
    float static_friction = 0.4f;    // read as `friction` where the scene file does not set it
    std::vector<uint32_t> pins;      // particle indices of the repaired, reordered mesh
    std::vector<PinRegion> pin_regions;
    sim::Colliders colliders;        // friction copied from `friction`
    topology::CutOptions cut;        // snapping and the volume policy of cuts and tears
    uint32_t fade_frames = 8;        // splats created by a cut fade in over this many frames
};

struct CameraOrbit {
    float degrees_per_second = 0.0f;  // about the camera target's y axis
};

// A camera path: eye and target keyframes, linearly interpolated, held after the last one.
struct CameraKey {
    float time = 0.0f;
    Vec3f eye, target;
};

// How each splat's covariance is shaped (render.splat_shape).
enum class SplatShape { round, surfel, deformed };
const char* splat_shape_name(SplatShape s);

struct RenderDesc {
    uint32_t width = 1280, height = 720;
    render::FrameInputs frame;  // camera, lighting, splat style, background
    bool sort = false;          // far-to-near sort for "over" blending
    // Where that sort runs; empty: chosen per device (render::preferred_sort).
    std::optional<render::SplatOrder> sort_on;
    render::SplatShading shading = render::SplatShading::fragment;
    render::SplatCarrier carrier = render::SplatCarrier::quad;
    // Skip the splats facing away from the eye while the body is closed (no open boundary):
    // nothing behind its near surface can show then.
    bool cull_back = true;
    // "round": every splat isotropic, as the paper draws them. "surfel": flattened onto the
    // plane of its normal (frame.style.surfel_thickness, from `surfel_thickness`), so a splat
    // seen edge-on at a fold or silhouette does not reach past it. "deformed": each boundary
    // particle's Gaussian is a flat disc carried by its triangle's deformation gradient
    // (anisotropic; sorted on the CPU when sorted).
    SplatShape splat_shape = SplatShape::round;
    float surfel_thickness = 0.1f;  // kept for the printer whatever the shape
    bool deformed_shapes() const { return splat_shape == SplatShape::deformed; }
    // "varying": each splat lit with the surface's normal turning across it, as the vertex
    // normals do across the mesh (splat/normal_field.h). "flat": one normal per splat (the
    // paper's): on a curved or crumpled body every disc shows as a facet.
    bool varying_normals = true;
    // `visibility`: what hides the surfaces behind under normalised blending (or the paper's
    // disc under "over"). "splats": each splat's opaque core writes depth (the disc: its own
    // depth). "mesh" (the default under normalised blending): the surface mesh itself
    // (frame.style.mesh_occluders, render/occluder_pass.h), and a splat fragment farther than
    // `occluder_tolerance` splat scales behind the surface the mesh shows at its pixel, or twice
    // that in front, is dropped: discs end at occluding contours and creases where the surface
    // does.
    // Three scales: a surfel's plane is that of its smoothed normal, which on a wrinkled surface
    // leaves the triangle under it by up to its reach times the turn between the two (the
    // deflating monkey opened pinholes on 0.94 % of its surface at one scale, 0.07 % at two,
    // none at three).
    float occluder_tolerance = 3.0f;
    // Draw the plane collider as a ground under the body, with a contact shadow.
    bool ground = true;
    CameraOrbit orbit;
    std::vector<CameraKey> path;  // sorted by time; when given, it replaces eye and target
    // Whether the file placed the camera ([render.camera]); without it the runtime frames the
    // models where the default view would miss them (scene/framing.h).
    bool camera_given = false;
    std::optional<render::SplatPath> splat_path;  // empty: the best the device has
    std::string environment_map;  // equirectangular PNG or .hdr (next to the scene file); empty: procedural sky
};

// Timeline events. Times in seconds from the start.
struct PressureEvent {
    float value = 1.0f;     // target k
    float duration = 0.0f;  // linear ramp from the current k; 0 = at once
    // The model whose pieces it ramps (0: [model], then the [[bodies]] in order); none: every
    // model that holds air.
    std::optional<uint32_t> body;
};
struct DragEvent {
    Vec3f from = Vec3f::Zero(), to = Vec3f::Zero();  // world points: the region about the particle nearest `from` is moved by to - from
    float duration = 1.0f;  // then released
    float stiffness = 0.5f;
    float radius = 0.0f;    // of the region held (world units); 0: sim::default_grab_radius
};
struct SpinEvent {
    Vec3f axis{0.0f, 1.0f, 0.0f};
    float degrees_per_second = 45.0f;  // the body turns about its centre
    float duration = 1.0f;
};
struct CutEvent {
    std::optional<std::array<Vec2f, 2>> segment;  // screen pixels, with the camera of that moment
    Vec2f screen{1280.0f, 720.0f};  // the resolution the pixels refer to (the scene file's)
    std::optional<std::pair<Vec3f, Vec3f>> plane;  // point and normal
};
struct TearEvent {
    float threshold = 1.5f;      // stretch ratio beyond which edges tear
    float tip_threshold = 0.0f;  // the same at a rip's rim (topology::TearOptions); 0: halfway to `threshold`
    uint32_t max_per_frame = 4;  // tears per frame
    float duration = 0.0f;       // tearing stays on this long; 0 = to the end
};
// The splats' opacity sigmoid(o) ramps linearly to `value` (Figure 13's sweep).
struct OpacityEvent {
    float value = 1.0f;     // in (0, 1)
    float duration = 0.0f;  // 0 = at once
};
using EventData = std::variant<PressureEvent, DragEvent, SpinEvent, CutEvent, TearEvent, OpacityEvent>;
struct Event {
    float time = 0.0f;
    EventData data;
};

// What a scene claims to show (its [expect] table, docs/scene-format.md): `pbdsplat check`
// runs `frames` frames (the whole timeline the claims are about) and holds each named figure of
// its report (scene/check_figures.h) to its bound.
struct ExpectBound {
    std::string figure;
    bool at_least = false;  // else at most
    double limit = 0.0;
};
struct ExpectDesc {
    uint32_t frames = 0;  // 0: the check's default
    std::vector<ExpectBound> bounds;
    bool empty() const { return frames == 0 && bounds.empty(); }
};

struct Scene {
    std::string name;        // file stem, or "default"
    std::string source_dir;  // directory of the scene file (models are looked up there first)
    ModelDesc model;
    // [model]'s own settings, as a body's; a scene of [[bodies]] alone takes its first body as
    // [model] with them.
    OwnSettings model_own;
    std::vector<BodyDesc> bodies;  // beside `model`
    // The file had no [model]: `model` is its first [[bodies]] entry (messages name it so).
    bool model_from_bodies = false;
    MaterialDesc material;
    SurfaceDesc surface;
    SimulationDesc simulation;
    RenderDesc render;
    std::vector<Event> events;  // sorted by time
    ExpectDesc expect;

    bool has_topology_events() const;
};

const char* event_type_name(const EventData& e);

// Model m's own settings (0: [model], then the [[bodies]] in order).
const OwnSettings& own_settings(const Scene& scene, size_t m);
// Model m's pressure factor k: its own, or the simulation's.
float pressure_of(const Scene& scene, size_t m);
// Model m's shape stiffness: its own, or the simulation's. And the stiffest model's: whether
// anything keeps a shape or answers as a solid.
float shape_stiffness_of(const Scene& scene, size_t m);
float stiffest_shape(const Scene& scene);

} // namespace pbdsplat::scene
