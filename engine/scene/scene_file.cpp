#include "scene/scene_file.h"

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <span>
#include <variant>

#include <toml++/toml.h>

#include "core/spelling.h"
#include "scene/check_figures.h"
#include "scene/key_hints.h"
#include "scene/scene_keys.h"

#include "asset/mesh_spec.h"
#include "render/environment.h"

namespace pbdsplat::scene {
namespace {

// Thrown inside the reader, caught at the top: the first error ends the parse.
struct ParseFailure {
    core::Error error;
};

class Reader {
public:
    explicit Reader(std::string file) : file_(std::move(file)) {}
    // Where the file is: relative paths inside it are taken from there.
    std::string directory() const { return std::filesystem::path(file_).parent_path().string(); }

    [[noreturn]] void fail(const toml::source_region& at, const std::string& what) const {
        throw ParseFailure{core::Error{what, file_ + ":" + std::to_string(at.begin.line) + ":" +
                                                 std::to_string(at.begin.column), 0}};
    }

    // One TOML table: values are taken by name, and finish() refuses any key not taken.
    class Table {
    public:
        Table(const Reader& r, const toml::table& t, std::string path) : r_(r), t_(t), path_(std::move(path)) {}
        ~Table() = default;

        bool has(const std::string& key) const {
            known_.insert(key);
            return t_.contains(key);
        }
        const toml::node* node(const std::string& key) {
            used_.insert(key);
            known_.insert(key);
            return t_.get(key);
        }
        std::string where(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }
        [[noreturn]] void fail(const std::string& key, const std::string& what) const { r_.fail(t_.get(key)->source(), what); }

        double number(const std::string& key, double fallback, double lo, double hi) {
            const toml::node* n = node(key);
            if (!n) return fallback;
            double v;
            if (auto i = n->as_integer()) v = double(i->get());
            else if (auto f = n->as_floating_point()) v = f->get();
            else r_.fail(n->source(), "'" + where(key) + "' must be a number");
            if (!std::isfinite(v)) r_.fail(n->source(), "'" + where(key) + "' must be finite");
            if (v < lo || v > hi)
                r_.fail(n->source(), "'" + where(key) + "' = " + fmt(v) + " is out of range [" + fmt(lo) + ", " + fmt(hi) + "]");
            return v;
        }
        float real(const std::string& key, float fallback, double lo, double hi) { return float(number(key, fallback, lo, hi)); }
        uint32_t count(const std::string& key, uint32_t fallback, uint32_t lo, uint32_t hi) {
            const toml::node* n = node(key);
            if (!n) return fallback;
            auto i = n->as_integer();
            if (!i) r_.fail(n->source(), "'" + where(key) + "' must be a whole number");
            if (i->get() < lo || i->get() > hi)
                r_.fail(n->source(), "'" + where(key) + "' = " + std::to_string(i->get()) + " is out of range [" +
                                         std::to_string(lo) + ", " + std::to_string(hi) + "]");
            return uint32_t(i->get());
        }
        bool flag(const std::string& key, bool fallback) {
            const toml::node* n = node(key);
            if (!n) return fallback;
            auto b = n->as_boolean();
            if (!b) r_.fail(n->source(), "'" + where(key) + "' must be true or false");
            return b->get();
        }
        std::string text(const std::string& key, const std::string& fallback) {
            const toml::node* n = node(key);
            if (!n) return fallback;
            auto s = n->as_string();
            if (!s) r_.fail(n->source(), "'" + where(key) + "' must be a string");
            return s->get();
        }
        // An enum by its name table (core/names.h).
        template <class E>
        E named(const std::string& key, E fallback, std::span<const core::EnumName<E>> table) {
            const std::string v = text(key, core::name_of(table, fallback));
            if (auto e = core::from_name(table, v)) return *e;
            not_one_of(key, v, core::names_of(table));
        }
        std::string choice(const std::string& key, const std::string& fallback, std::initializer_list<const char*> options) {
            const std::string v = text(key, fallback);
            for (const char* o : options)
                if (v == o) return v;
            not_one_of(key, v, std::vector<std::string>(options.begin(), options.end()));
        }
        // "'render.blend' must be one of over, additive, normalised, not 'normalized' (did you
        // mean 'normalised'?)".
        [[noreturn]] void not_one_of(const std::string& key, const std::string& v, const std::vector<std::string>& options) const {
            std::string all;
            for (const std::string& o : options) all += (all.empty() ? "" : ", ") + o;
            const auto near = core::nearest_spelling(v, options);
            r_.fail(t_.get(key)->source(), "'" + where(key) + "' must be one of " + all + ", not '" + v + "'" +
                                               (near ? " (did you mean '" + *near + "'?)" : std::string()));
        }
        template <int N>
        Eigen::Matrix<float, N, 1> vec(const std::string& key, const Eigen::Matrix<float, N, 1>& fallback, double lo = -1e6,
                                       double hi = 1e6) {
            const toml::node* n = node(key);
            if (!n) return fallback;
            auto a = n->as_array();
            if (!a || a->size() != size_t(N)) r_.fail(n->source(), "'" + where(key) + "' must be an array of " + std::to_string(N) + " numbers");
            Eigen::Matrix<float, N, 1> out;
            for (int k = 0; k < N; ++k) {
                const toml::node& e = *a->get(size_t(k));
                double v;
                if (auto i = e.as_integer()) v = double(i->get());
                else if (auto f = e.as_floating_point()) v = f->get();
                else r_.fail(e.source(), "'" + where(key) + "' must be an array of " + std::to_string(N) + " numbers");
                if (!std::isfinite(v) || v < lo || v > hi)
                    r_.fail(e.source(), "'" + where(key) + "' element " + fmt(v) + " is out of range [" + fmt(lo) + ", " + fmt(hi) + "]");
                out[k] = float(v);
            }
            return out;
        }
        // One factor, or one per axis.
        ModelScale scale(const std::string& key, const ModelScale& fallback, double lo, double hi) {
            const toml::node* n = node(key);
            if (!n) return fallback;
            if (n->is_array()) {
                if (n->as_array()->size() != 3)
                    r_.fail(n->source(), "'" + where(key) + "' must be a number or an array of 3 numbers (one per axis)");
                return ModelScale{vec<3>(key, fallback.axes, lo, hi)};
            }
            if (!n->as_integer() && !n->as_floating_point())
                r_.fail(n->source(), "'" + where(key) + "' must be a number or an array of 3 numbers (one per axis)");
            return ModelScale{Vec3f::Constant(real(key, 1.0f, lo, hi))};
        }
        const toml::table* table(const std::string& key) {
            const toml::node* n = node(key);
            if (!n) return nullptr;
            if (!n->is_table()) r_.fail(n->source(), "'" + where(key) + "' must be a table");
            return n->as_table();
        }
        const toml::array* array(const std::string& key) {
            const toml::node* n = node(key);
            if (!n) return nullptr;
            if (!n->is_array()) r_.fail(n->source(), "'" + where(key) + "' must be an array");
            return n->as_array();
        }
        void finish() const {
            for (const auto& [k, v] : t_)
                if (!used_.count(std::string(k.str())))
                    r_.fail(k.source().begin.line ? k.source() : v.source(),
                            "unknown key '" + where(std::string(k.str())) + "'" + unknown_key_hint(k.str(), known_, path_));
        }
        const toml::table& raw() const { return t_; }
        const toml::source_region& source_of(const std::string& key) const { return t_.get(key)->source(); }

    private:
        static std::string fmt(double v) {
            std::ostringstream s;
            s << v;
            return s.str();
        }
        const Reader& r_;
        const toml::table& t_;
        std::string path_;
        std::set<std::string> used_;
        // Every key looked up, read or only asked about: what a misspelt key is compared with.
        mutable std::set<std::string> known_;
    };

private:
    std::string file_;
};

using namespace keys;

template <class D>
void read_keys(Reader::Table& t, D& d, std::span<const Key<D>> keys) {
    for (const Key<D>& k : keys)
        std::visit(Overloaded{[&](typename Key<D>::Real f) { f(d) = t.real(k.name, f(d), k.lo, k.hi); },
                              [&](typename Key<D>::Count f) { f(d) = t.count(k.name, f(d), uint32_t(k.lo), uint32_t(k.hi)); },
                              [&](typename Key<D>::Flag f) { f(d) = t.flag(k.name, f(d)); },
                              [&](typename Key<D>::Vec3 f) { f(d) = t.vec<3>(k.name, f(d), k.lo, k.hi); },
                              [&](typename Key<D>::Text f) { f(d) = t.text(k.name, f(d)); },
                              [&](typename Key<D>::Scale f) { f(d) = t.scale(k.name, f(d), k.lo, k.hi); }},
                   k.at);
}

Vec3f normalized_or_fail(const Reader& r, const toml::node* n, const Vec3f& v, const std::string& key) {
    if (v.norm() < 1e-6f) r.fail(n ? n->source() : toml::source_region{}, "'" + key + "' must not be the zero vector");
    return v.normalized();
}

// A procedural mesh's parameters are refused here, where the key's line is known; a file is
// read when the scene is built. The model's up axis is read here too, beside the plain keys.
void check_mesh(Reader::Table& t, ModelDesc& m) {
    m.up = t.named<asset::UpAxis>("up", asset::UpAxis::file_default, asset::k_up_axis_names);
    if (!t.has("mesh") || !asset::is_procedural_spec(m.mesh)) return;
    if (const core::Status st = asset::check_procedural_spec(m.mesh); !st.ok()) t.fail("mesh", st.error().message);
}

// The settings a model may name for itself, in [model] or a [[bodies]] entry.
OwnSettings read_own(Reader::Table& t) {
    OwnSettings o;
    if (t.has("color")) o.color = t.vec<3>("color", Vec3f::Ones(), 0.0, 1.0);
    if (t.has("particles")) o.particles = t.count("particles", 0, 0, 10'000'000);
    if (t.has("mass")) o.mass = t.real("mass", 1.0f, 1e-6, 1e6);
    if (t.has("shape_stiffness")) o.shape_stiffness = t.real("shape_stiffness", 0.0f, 0.0, 1.0);
    if (t.has("damping")) o.damping = t.real("damping", 0.0f, 0.0, 1e3);
    if (t.has("deform_damping")) o.deform_damping = t.real("deform_damping", 0.0f, 0.0, 1e3);
    if (t.has("pressure")) o.pressure = t.real("pressure", 1.0f, 0.01, 100.0);
    if (t.has("stiffness")) o.stiffness = t.real("stiffness", 1.0f, 1e-4, 1.0);
    if (t.has("compliance")) o.compliance = t.real("compliance", 0.0f, 0.0, 1e3);
    return o;
}

void read_model(const Reader& r, Reader::Table& t, Scene& scene) {
    read_keys<ModelDesc>(t, scene.model, k_model_keys);
    check_mesh(t, scene.model);
    scene.model_own = read_own(t);
    (void)r;
    t.finish();
}

// A scene of [[bodies]] alone: its first body is [model] (not a default icosphere beside them).
// With one model, its colour is the material's.
void settle_models(bool model_given, Scene& scene) {
    if (!model_given && !scene.bodies.empty()) {
        BodyDesc& first = scene.bodies.front();
        scene.model = std::move(first.model);
        scene.model_own = first.own;
        scene.bodies.erase(scene.bodies.begin());
        scene.model_from_bodies = true;
    }
    if (scene.bodies.empty() && scene.model_own.color) {
        scene.material.color = *scene.model_own.color;
        scene.model_own.color.reset();
    }
}

BodyDesc read_body(const Reader& r, const toml::node& n) {
    if (!n.is_table()) r.fail(n.source(), "'bodies' holds tables ([[bodies]] with mesh = \"...\" and the [model] keys)");
    Reader::Table t(r, *n.as_table(), "bodies");
    BodyDesc b;
    if (!t.has("mesh")) r.fail(n.source(), "a [[bodies]] entry needs 'mesh' (a model file or a procedural mesh such as \"box:1\")");
    read_keys<ModelDesc>(t, b.model, k_model_keys);
    check_mesh(t, b.model);
    b.own = read_own(t);
    t.finish();
    return b;
}

// [expect]: frames, and the figures held at_least / at_most a number.
void read_expect(const Reader& r, Reader::Table& t, ExpectDesc& e) {
    e.frames = t.count("frames", 0, 1, 1000000);
    for (const bool at_least : {true, false}) {
        const char* side = at_least ? "at_least" : "at_most";
        const toml::table* bounds = t.table(side);
        if (!bounds) continue;
        Reader::Table b(r, *bounds, std::string("expect.") + side);
        for (const auto& [key, value] : *bounds) {
            const std::string figure(key.str());
            if (!is_check_figure(figure)) {
                std::string all;
                for (const CheckFigure& f : check_figures()) all += (all.empty() ? "" : ", ") + std::string(f.name);
                r.fail(key.source().begin.line ? key.source() : value.source(),
                       "'" + b.where(figure) + "' is not a figure pbdsplat check measures (" + all + ")");
            }
            e.bounds.push_back({figure, at_least, b.number(figure, 0.0, -1e9, 1e9)});
        }
        b.finish();
    }
    t.finish();
}

void read_material(Reader::Table& t, MaterialDesc& m) {
    read_keys<MaterialDesc>(t, m, k_material_keys);
    if (t.has("interior_color")) m.interior_color = t.vec<3>("interior_color", Vec3f::Ones(), 0.0, 1.0);
    t.finish();
}

void read_surface(Reader::Table& t, SurfaceDesc& d) {
    d.mode = t.named<SurfaceMode>("mode", SurfaceMode::boundary, k_surface_mode_names);
    read_keys<SurfaceDesc>(t, d, k_surface_keys);
    for (const auto& k : k_advanced_keys)
        if (t.has(k.name))
            t.fail(k.name, "'" + t.where(k.name) + "' is one of the density control's internals: it belongs in the [advanced] table");
    t.finish();
}

void read_advanced(Reader::Table& t, SurfaceDesc& d) {
    read_keys<SurfaceDesc>(t, d, k_advanced_keys);
    t.finish();
}

void read_simulation(const Reader& r, Reader::Table& t, SimulationDesc& s) {
    sim::SolverSettings& solver = s.solver;
    solver.mode = t.named<sim::SolverMode>("mode", sim::SolverMode::paper, sim::k_solver_mode_names);
    read_keys<SimulationDesc>(t, s, k_simulation_keys);
    s.substeps_given = t.has("substeps");
    if (t.has("particles")) s.particles = t.count("particles", 0, 0, 10'000'000);
    s.cut.volume = t.named<topology::VolumePolicy>("cut_volume", topology::VolumePolicy::cap, topology::k_volume_policy_names);
    if (const toml::array* pins = t.array("pins"))
        for (const toml::node& p : *pins) {
            auto i = p.as_integer();
            if (!i || i->get() < 0 || i->get() > 0x7fffffff) r.fail(p.source(), "'simulation.pins' holds particle indices (whole numbers >= 0)");
            s.pins.push_back(uint32_t(i->get()));
        }
    if (const toml::array* regions = t.array("pin_regions"))
        for (const toml::node& n : *regions) {
            if (!n.is_table()) r.fail(n.source(), "'simulation.pin_regions' holds tables {min = [...], max = [...]}");
            Reader::Table region(r, *n.as_table(), "simulation.pin_regions");
            PinRegion p{region.vec<3>("min", Vec3f::Zero()), region.vec<3>("max", Vec3f::Zero())};
            if ((p.min.array() > p.max.array()).any()) r.fail(n.source(), "pin region: min must not exceed max");
            region.finish();
            s.pin_regions.push_back(p);
        }
    if (const toml::array* colliders = t.array("colliders"))
        for (const toml::node& n : *colliders) {
            if (!n.is_table()) r.fail(n.source(), "'simulation.colliders' holds tables");
            Reader::Table c(r, *n.as_table(), "simulation.colliders");
            const std::string type = c.choice("type", "plane", {"plane", "sphere", "box"});
            if (type == "plane") {
                sim::GroundPlane g;
                g.normal = normalized_or_fail(r, c.raw().get("normal"), c.vec<3>("normal", g.normal), "normal");
                g.offset = c.real("offset", g.offset, -1e6, 1e6);
                if (s.colliders.ground) r.fail(n.source(), "only one plane collider is supported");
                s.colliders.ground = g;
            } else if (type == "sphere") {
                sim::SphereCollider sp;
                sp.center = c.vec<3>("center", sp.center);
                sp.radius = c.real("radius", sp.radius, 1e-6, 1e6);
                s.colliders.spheres.push_back(sp);
            } else {
                sim::BoxCollider b;
                b.center = c.vec<3>("center", b.center);
                b.half_extents = c.vec<3>("half_extents", b.half_extents, 1e-6, 1e6);
                const Vec3f deg = c.vec<3>("rotate_degrees", Vec3f::Zero(), -3600, 3600);
                b.rotation = Eigen::AngleAxisf(math::radians(deg.z()), Vec3f::UnitZ()) *
                             Eigen::AngleAxisf(math::radians(deg.y()), Vec3f::UnitY()) *
                             Eigen::AngleAxisf(math::radians(deg.x()), Vec3f::UnitX());
                s.colliders.boxes.push_back(b);
            }
            c.finish();
        }
    if (!t.has("static_friction")) s.static_friction = s.friction;
    s.colliders.friction = {s.friction, s.static_friction};
    s.solver.contact.friction = s.colliders.friction;
    t.finish();
}

// The splats' look and the frame: size, blending, sorting, footprint, shape, depth.
void read_splat_look(const Reader& r, Reader::Table& t, RenderDesc& d) {
    read_keys<RenderDesc>(t, d, k_render_keys);
    render::SplatStyle& style = d.frame.style;
    const std::string blend = t.choice("blend", "over", {"over", "additive", "normalised"});
    style.blend = blend == "additive" ? render::Blend::additive : blend == "normalised" ? render::Blend::normalised : render::Blend::over;
    const std::string sort_on = t.choice("sort_on", "auto", {"auto", "cpu", "gpu"});
    if (sort_on == "cpu") d.sort_on = render::SplatOrder::cpu;
    else if (sort_on == "gpu") d.sort_on = render::SplatOrder::gpu;
    d.shading = t.choice("shading", "fragment", {"fragment", "corner"}) == "corner" ? render::SplatShading::corner
                                                                                    : render::SplatShading::fragment;
    style.footprint = t.named<render::Footprint>("footprint", style.footprint, render::k_footprint_names);
    if (style.blend == render::Blend::normalised && style.footprint != render::Footprint::gaussian)
        r.fail(t.source_of("blend"), "'render.blend' = \"normalised\" weighs each splat by its Gaussian falloff: it needs "
                                     "'render.footprint' = \"gaussian\" (the paper's flat disc has no falloff to weigh by)");
    if (style.kappa > 0.0f && style.kappa < 0.5f)
        r.fail(t.source_of("kappa"), "'render.kappa' = " + std::to_string(style.kappa) +
                                         " is too small to draw: 0 (the footprint's default) or at least 0.5");
    // Mesh occluders by default where they serve: every shipped normalised scene measured
    // fewer specks and holes and a closer outline with them (docs/BENCHMARKS.md, "Mesh occluders").
    const bool normalised = style.blend == render::Blend::normalised;
    style.mesh_occluders = t.choice("visibility", normalised ? "mesh" : "splats", {"splats", "mesh"}) == "mesh";
    if (style.mesh_occluders && !render::occluded_style(style))
        r.fail(t.source_of("visibility"), "'render.visibility' = \"mesh\" sets what hides the surfaces behind under normalised "
                                          "blending or the paper's disc: it needs 'render.blend' = \"normalised\", or "
                                          "'render.footprint' = \"paper\" with 'render.blend' = \"over\"");
    style.sharpness = t.vec<2>("sharpness", style.sharpness, 0.1, 4.0);
    d.carrier = t.named<render::SplatCarrier>("carrier", render::SplatCarrier::quad, render::k_splat_carrier_names);
    const std::string shape = t.choice("splat_shape", "round", {"round", "surfel", "deformed"});
    d.splat_shape = shape == "surfel" ? SplatShape::surfel : shape == "deformed" ? SplatShape::deformed : SplatShape::round;
    style.surfel_thickness = d.splat_shape == SplatShape::surfel ? d.surfel_thickness : 0.0f;
    if (style.thin_below > 0.0f && (!normalised || d.splat_shape == SplatShape::deformed))
        r.fail(t.source_of("thin_below"), "'render.thin_below' draws small splats fewer and larger, weighed against their "
                                          "neighbours: it needs 'render.blend' = \"normalised\" and round or surfel splats "
                                          "(not 'splat_shape' = \"deformed\")");
    d.varying_normals = t.choice("splat_normals", "varying", {"varying", "flat"}) == "varying";
    const Vec3f bg = t.vec<3>("background", Vec3f(d.frame.background.head<3>()), 0.0, 1.0);
    d.frame.background = Vec4f(bg.x(), bg.y(), bg.z(), 1.0f);
}

void read_camera(const Reader& r, Reader::Table& t, RenderDesc& d) {
    if (const toml::table* cam = t.table("camera")) {
        Reader::Table c(r, *cam, "render.camera");
        render::Camera& k = d.frame.camera;
        read_keys<render::Camera>(c, k, k_camera_keys);
        d.orbit.degrees_per_second = c.real("orbit_degrees_per_second", d.orbit.degrees_per_second, -3600, 3600);
        if ((k.eye - k.target).norm() < 1e-6f) r.fail(cam->source(), "'render.camera': eye and target coincide");
        if (const toml::array* path = c.array("path")) {
            for (const toml::node& n : *path) {
                if (!n.is_table()) r.fail(n.source(), "'render.camera.path' holds tables {time, eye, target}");
                Reader::Table key_table(r, *n.as_table(), "render.camera.path");
                CameraKey key{key_table.real("time", 0.0f, 0.0, 1e6), key_table.vec<3>("eye", d.frame.camera.eye),
                              key_table.vec<3>("target", d.frame.camera.target)};
                if ((key.eye - key.target).norm() < 1e-6f) r.fail(n.source(), "camera path key: eye and target coincide");
                if (!d.path.empty() && key.time <= d.path.back().time)
                    r.fail(n.source(), "camera path keys must be in increasing time");
                key_table.finish();
                d.path.push_back(key);
            }
        }
        d.camera_given = c.has("eye") || c.has("target") || !d.path.empty();
        c.finish();
    }
}

void read_environment(const Reader& r, Reader::Table& t, RenderDesc& d) {
    render::Environment& env = d.frame.lighting.environment;
    env.sampling = t.named<render::EnvSampling>("environment", render::EnvSampling::position, render::k_env_sampling_names);
    if (t.has("environment_map")) {
        d.environment_map = t.text("environment_map", "");
        if (d.environment_map.empty())
            r.fail(t.source_of("environment_map"), "'render.environment_map' must name a PNG or .hdr file, or procedural:sky or procedural:studio");
        if (d.environment_map.rfind(render::k_procedural_prefix, 0) == 0) {
            if (!render::is_procedural_map_name(d.environment_map))
                r.fail(t.source_of("environment_map"), "'render.environment_map': unknown procedural map '" + d.environment_map +
                                                           "' (procedural:sky or procedural:studio)");
        } else {
            const std::filesystem::path map(d.environment_map);
            if (map.is_relative()) d.environment_map = (std::filesystem::path(r.directory()) / map).string();
            if (!std::filesystem::exists(d.environment_map))
                r.fail(t.source_of("environment_map"), "'render.environment_map': no such file '" + d.environment_map + "'");
        }
    }
}

// The direct lights: the list of point, spot and directional lights, and the key light.
void read_lights(const Reader& r, Reader::Table& t, RenderDesc& d) {
    if (const toml::array* lights = t.array("lights")) {
        for (const toml::node& n : *lights) {
            if (!n.is_table()) r.fail(n.source(), "'render.lights' holds tables {type, position, direction, color, intensity, ...}");
            if (d.frame.lighting.lights.size() == render::k_max_lights)
                r.fail(n.source(), "'render.lights': at most " + std::to_string(render::k_max_lights) + " lights");
            Reader::Table lt(r, *n.as_table(), "render.lights");
            render::Light l;
            const std::string type = lt.choice("type", "point", {"point", "spot", "directional"});
            l.type = type == "spot" ? render::LightType::spot : type == "directional" ? render::LightType::directional : render::LightType::point;
            read_keys<render::Light>(lt, l, k_light_keys);
            if (l.direction.norm() < 1e-6f) r.fail(n.source(), "'render.lights.direction' must not be the zero vector");
            if (l.outer_degrees <= l.inner_degrees) r.fail(n.source(), "'render.lights': outer_degrees must exceed inner_degrees");
            lt.finish();
            d.frame.lighting.lights.push_back(l);
        }
    }
    if (const toml::table* light = t.table("light")) {
        Reader::Table l(r, *light, "render.light");
        render::Lighting& g = d.frame.lighting;
        read_keys<render::Lighting>(l, g, k_key_light_keys);
        if (g.direction.norm() < 1e-6f) r.fail(light->source(), "'render.light.direction' must not be the zero vector");
        l.finish();
    }
}

void read_render(const Reader& r, Reader::Table& t, RenderDesc& d) {
    read_splat_look(r, t, d);
    read_camera(r, t, d);
    const std::string path = t.choice("path", "auto", {"auto", "gs", "mesh", "vertex"});
    if (path == "gs") d.splat_path = render::SplatPath::geometry;
    else if (path == "mesh") d.splat_path = render::SplatPath::mesh;
    else if (path == "vertex") d.splat_path = render::SplatPath::vertex;
    read_environment(r, t, d);
    read_lights(r, t, d);
    t.finish();
}

PressureEvent read_pressure(const Reader& r, Reader::Table& t, const toml::node& n, size_t models) {
    PressureEvent p;
    if (!t.has("value")) r.fail(n.source(), "a pressure event needs 'value' (the pressure factor k to reach, 0.01 to 100)");
    p.value = t.real("value", p.value, 0.01, 100.0);
    p.duration = t.real("duration", p.duration, 0.0, 1e6);
    if (t.has("body")) {
        p.body = t.count("body", 0, 0, 1'000'000);
        if (*p.body >= models)
            r.fail(t.source_of("body"), "'events.body' = " + std::to_string(*p.body) + " names no model: the scene has " + std::to_string(models) +
                                            " (0 is [model], or the first [[bodies]] entry without one; then the [[bodies]] in order)");
    }
    return p;
}

// `models`: how many models the scene holds ([model] and the [[bodies]]), which a pressure
// event's `body` names.
Event read_event(const Reader& r, const toml::node& n, size_t models) {
    if (!n.is_table()) r.fail(n.source(), "each [[events]] entry must be a table");
    Reader::Table t(r, *n.as_table(), "events");
    Event e;
    e.time = t.real("time", 0.0f, 0.0, 1e6);
    const std::string type = t.choice("type", "pressure", {"pressure", "drag", "spin", "cut", "tear", "opacity"});
    if (!t.has("type")) r.fail(n.source(), "an event needs a 'type' (pressure, drag, spin, cut, tear)");
    if (type == "opacity") {
        OpacityEvent o;
        if (!t.has("value")) r.fail(n.source(), "an opacity event needs 'value' (the opacity to reach, 0.01 to 0.999)");
        o.value = t.real("value", o.value, 0.01, 0.999);
        o.duration = t.real("duration", o.duration, 0.0, 1e6);
        e.data = o;
    } else if (type == "pressure") {
        e.data = read_pressure(r, t, n, models);
    } else if (type == "drag") {
        DragEvent d;
        if (!t.has("from") || !t.has("to")) r.fail(n.source(), "a drag event needs 'from' and 'to'");
        d.from = t.vec<3>("from", d.from);
        d.to = t.vec<3>("to", d.to);
        d.duration = t.real("duration", d.duration, 0.0, 1e6);
        d.stiffness = t.real("stiffness", d.stiffness, 1e-3, 1.0);
        d.radius = t.real("radius", d.radius, 0.0, 1e6);
        e.data = d;
    } else if (type == "spin") {
        SpinEvent s;
        if (!t.has("axis") || !t.has("degrees_per_second"))
            r.fail(n.source(), "a spin event needs 'axis' ([x, y, z]) and 'degrees_per_second'");
        s.axis = normalized_or_fail(r, n.as_table()->get("axis"), t.vec<3>("axis", s.axis), "axis");
        s.degrees_per_second = t.real("degrees_per_second", s.degrees_per_second, -36000, 36000);
        s.duration = t.real("duration", s.duration, 0.0, 1e6);
        e.data = s;
    } else if (type == "cut") {
        CutEvent c;
        const bool seg = t.has("from") || t.has("to");
        const bool plane = t.has("point") || t.has("normal");
        if (seg == plane) r.fail(n.source(), "a cut event needs either a screen segment ('from', 'to' in pixels) or a plane ('point', 'normal')");
        if (seg && !(t.has("from") && t.has("to"))) r.fail(n.source(), "a cut along a screen segment needs both 'from' and 'to' (pixels)");
        if (plane && !(t.has("point") && t.has("normal"))) r.fail(n.source(), "a cut by a plane needs both 'point' and 'normal'");
        if (seg) c.segment = std::array<Vec2f, 2>{t.vec<2>("from", Vec2f::Zero(), -1e5, 1e5), t.vec<2>("to", Vec2f::Zero(), -1e5, 1e5)};
        else c.plane = std::pair<Vec3f, Vec3f>{t.vec<3>("point", Vec3f::Zero()),
                                               normalized_or_fail(r, n.as_table()->get("normal"), t.vec<3>("normal", Vec3f::UnitY()), "normal")};
        e.data = c;
    } else {
        TearEvent te;
        te.threshold = t.real("threshold", te.threshold, 1.01, 100.0);
        if (t.has("tip_threshold")) te.tip_threshold = t.real("tip_threshold", te.threshold, 1.005, double(te.threshold));
        te.max_per_frame = t.count("max_per_frame", te.max_per_frame, 1, 1000);
        te.duration = t.real("duration", te.duration, 0.0, 1e6);
        e.data = te;
    }
    t.finish();
    return e;
}

} // namespace

core::Result<Scene> parse_scene(const std::string& text, const std::string& name) {
    Scene scene;
    scene.name = std::filesystem::path(name).stem().string();
    scene.source_dir = std::filesystem::path(name).parent_path().string();
    Reader r(name);
    try {
        toml::table root;
        try {
            root = toml::parse(text, name);
        } catch (const toml::parse_error& e) {
            r.fail(e.source(), std::string(e.description()));
        }
        Reader::Table top(r, root, "");
        const toml::table* model_table = top.table("model");
        if (model_table) {
            Reader::Table m(r, *model_table, "model");
            read_model(r, m, scene);
        }
        if (const toml::array* bodies = top.array("bodies"))
            for (const toml::node& n : *bodies) scene.bodies.push_back(read_body(r, n));
        if (const toml::table* t = top.table("material")) {
            Reader::Table m(r, *t, "material");
            read_material(m, scene.material);
        }
        if (const toml::table* t = top.table("surface")) {
            Reader::Table d(r, *t, "surface");
            read_surface(d, scene.surface);
        }
        if (const toml::table* t = top.table("advanced")) {
            Reader::Table a(r, *t, "advanced");
            read_advanced(a, scene.surface);
        }
        if (const toml::table* t = top.table("simulation")) {
            Reader::Table s(r, *t, "simulation");
            read_simulation(r, s, scene.simulation);
        }
        if (const toml::table* t = top.table("render")) {
            Reader::Table d(r, *t, "render");
            read_render(r, d, scene.render);
        }
        // Without [model], the first [[bodies]] entry is model 0 (settle_models).
        const size_t models = model_table || scene.bodies.empty() ? 1 + scene.bodies.size() : scene.bodies.size();
        if (const toml::array* events = top.array("events"))
            for (const toml::node& n : *events) scene.events.push_back(read_event(r, n, models));
        if (const toml::table* t = top.table("expect")) {
            Reader::Table e(r, *t, "expect");
            read_expect(r, e, scene.expect);
        }
        top.finish();
        settle_models(model_table != nullptr, scene);
    } catch (const ParseFailure& f) {
        // The location is in `file` ("name:line:column"); keep it as the error's file.
        return f.error;
    }
    std::stable_sort(scene.events.begin(), scene.events.end(), [](const Event& a, const Event& b) { return a.time < b.time; });
    // Segment pixels refer to the resolution written in the file, whatever a run overrides.
    for (Event& e : scene.events)
        if (auto* c = std::get_if<CutEvent>(&e.data)) c->screen = Vec2f(float(scene.render.width), float(scene.render.height));
    return scene;
}

core::Result<Scene> load_scene(const std::string& path) {
    std::ifstream file(path, std::ios::binary);
    if (!file) return core::make_error(path, 0, "cannot open the scene file (does it exist and is it readable?)");
    std::ostringstream text;
    text << file.rdbuf();
    return parse_scene(text.str(), path);
}

} // namespace pbdsplat::scene
