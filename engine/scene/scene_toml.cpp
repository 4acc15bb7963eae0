// Scene -> TOML: every key a reader takes, written back so that parse(to_toml(s)) == s.
#include <cstdio>
#include <ostream>
#include <span>
#include <sstream>
#include <string_view>
#include <vector>

#include "scene/scene_file.h"
#include "scene/scene_keys.h"

namespace pbdsplat::scene {

using namespace keys;

namespace {
std::string num(double v) {
    char buf[40];
    std::snprintf(buf, sizeof(buf), "%.9g", v);
    std::string s = buf;
    if (s.find_first_of(".eEn") == std::string::npos) s += ".0";  // keep it a TOML float
    return s;
}
template <int N>
std::string vec(const Eigen::Matrix<float, N, 1>& v) {
    std::string s = "[";
    for (int k = 0; k < N; ++k) s += (k ? ", " : "") + num(double(v[k]));
    return s + "]";
}
// A TOML basic string: quotes, backslashes and control characters escaped, so that any name,
// a newline in it included, prints back into a file that parses (the fuzz corpus holds one).
std::string toml_string(const std::string& t) {
    std::string o = "\"";
    for (const char c : t) {
        const auto u = static_cast<unsigned char>(c);
        if (c == '"' || c == '\\') {
            o += '\\';
            o += c;
        } else if (u < 0x20 || u == 0x7f) {
            char buf[8];
            std::snprintf(buf, sizeof(buf), "\\u%04x", unsigned(u));
            o += buf;
        } else {
            o += c;
        }
    }
    return o + "\"";
}

// One "name = value" per line, or `separator`-joined (an inline table's entries).
template <class D>
void write_keys(std::ostream& o, const D& section, std::span<const Key<D>> keys, const char* separator = nullptr) {
    D d = section;  // the accessors take the struct as the reader fills it
    for (const Key<D>& k : keys) {
        if (separator && &k != keys.data()) o << separator;
        o << k.name << " = ";
        std::visit(Overloaded{[&](typename Key<D>::Real f) { o << num(f(d)); }, [&](typename Key<D>::Count f) { o << f(d); },
                              [&](typename Key<D>::Flag f) { o << (f(d) ? "true" : "false"); },
                              [&](typename Key<D>::Vec3 f) { o << vec<3>(f(d)); }, [&](typename Key<D>::Text f) { o << toml_string(f(d)); },
                              [&](typename Key<D>::Scale f) {
                                  const ModelScale& s = f(d);
                                  if (s.uniform()) o << num(s.axes.x());
                                  else o << vec<3>(s.axes);
                              }},
                   k.at);
        if (!separator) o << "\n";
    }
}

void write_up(std::ostream& o, const ModelDesc& m) {
    if (m.up != asset::UpAxis::file_default) o << "up = \"" << core::name_of<asset::UpAxis>(asset::k_up_axis_names, m.up) << "\"\n";
}

// A model's own settings, those it names.
void write_own(std::ostream& o, const OwnSettings& own) {
    if (const auto& c = own.color) o << "color = [" << num(c->x()) << ", " << num(c->y()) << ", " << num(c->z()) << "]\n";
    if (own.particles) o << "particles = " << *own.particles << "\n";
    if (own.mass) o << "mass = " << num(*own.mass) << "\n";
    if (own.shape_stiffness) o << "shape_stiffness = " << num(*own.shape_stiffness) << "\n";
    if (own.damping) o << "damping = " << num(*own.damping) << "\n";
    if (own.deform_damping) o << "deform_damping = " << num(*own.deform_damping) << "\n";
    if (own.pressure) o << "pressure = " << num(*own.pressure) << "\n";
    if (own.stiffness) o << "stiffness = " << num(*own.stiffness) << "\n";
    if (own.compliance) o << "compliance = " << num(*own.compliance) << "\n";
}

// One writer per section, in the order a reader meets them.
void write_model_material_surface(std::ostream& o, const Scene& sc) {
    o << "[model]\n";
    write_keys<ModelDesc>(o, sc.model, k_model_keys);
    write_up(o, sc.model);
    write_own(o, sc.model_own);
    for (const BodyDesc& b : sc.bodies) {
        o << "\n[[bodies]]\n";
        write_keys<ModelDesc>(o, b.model, k_model_keys);
        write_up(o, b.model);
        write_own(o, b.own);
    }
    o << "\n[material]\n";
    write_keys<MaterialDesc>(o, sc.material, k_material_keys);
    if (const auto& c = sc.material.interior_color)
        o << "interior_color = [" << num(c->x()) << ", " << num(c->y()) << ", " << num(c->z()) << "]\n";
    o << "\n[surface]\nmode = \"" << core::name_of<SurfaceMode>(k_surface_mode_names, sc.surface.mode) << "\"\n";
    write_keys<SurfaceDesc>(o, sc.surface, k_surface_keys);
    o << "\n[advanced]\n# the density control's internals, chosen from measurements: see docs/scene-format.md\n";
    write_keys<SurfaceDesc>(o, sc.surface, k_advanced_keys);
    o << "\n";
}

void write_simulation(std::ostream& o, const Scene& sc) {
    const SimulationDesc& s = sc.simulation;
    o << "[simulation]\nmode = \"" << core::name_of<sim::SolverMode>(sim::k_solver_mode_names, s.solver.mode) << "\"\n";
    // Substeps the file did not set stay unset: loading chooses them for the model's size.
    std::vector<Key<SimulationDesc>> keys;
    for (const Key<SimulationDesc>& k : k_simulation_keys)
        if (s.substeps_given || std::string_view(k.name) != "substeps") keys.push_back(k);
    write_keys<SimulationDesc>(o, s, keys);
    o << "cut_volume = \"" << topology::volume_policy_name(s.cut.volume) << "\"";
    if (s.particles) o << "\nparticles = " << *s.particles;
    o << "\npins = [";
    for (size_t i = 0; i < s.pins.size(); ++i) o << (i ? ", " : "") << s.pins[i];
    o << "]\npin_regions = [";
    for (size_t i = 0; i < s.pin_regions.size(); ++i)
        o << (i ? ", " : "") << "{ min = " << vec<3>(s.pin_regions[i].min) << ", max = " << vec<3>(s.pin_regions[i].max) << " }";
    o << "]\ncolliders = [";
    bool first = true;
    auto sep = [&] { o << (first ? "\n  " : ",\n  "); first = false; };
    if (s.colliders.ground) {
        sep();
        o << "{ type = \"plane\", normal = " << vec<3>(s.colliders.ground->normal) << ", offset = " << num(s.colliders.ground->offset) << " }";
    }
    for (const auto& sp : s.colliders.spheres) {
        sep();
        o << "{ type = \"sphere\", center = " << vec<3>(sp.center) << ", radius = " << num(sp.radius) << " }";
    }
    for (const auto& b : s.colliders.boxes) {
        sep();
        const Vec3f deg = b.rotation.toRotationMatrix().eulerAngles(2, 1, 0).reverse() * (180.0f / k_pi);
        o << "{ type = \"box\", center = " << vec<3>(b.center) << ", half_extents = " << vec<3>(b.half_extents)
          << ", rotate_degrees = " << vec<3>(deg) << " }";
    }
    o << (first ? "]\n\n" : "\n]\n\n");
}

void write_render(std::ostream& o, const Scene& sc) {
    const RenderDesc& d = sc.render;
    const render::Camera& c = d.frame.camera;
    const render::Lighting& l = d.frame.lighting;
    o << "[render]\n";
    write_keys<RenderDesc>(o, d, k_render_keys);
    o << "blend = "
      << (d.frame.style.blend == render::Blend::additive     ? "\"additive\""
          : d.frame.style.blend == render::Blend::normalised ? "\"normalised\""
                                                             : "\"over\"")
      << "\nsort_on = \"" << (d.sort_on ? render::splat_order_name(*d.sort_on) : "auto") << "\"\nshading = \""
      << (d.shading == render::SplatShading::corner ? "corner" : "fragment") << "\""
      << "\nfootprint = \"" << render::footprint_name(d.frame.style.footprint) << "\""
      << "\nsharpness = " << vec<2>(d.frame.style.sharpness)
      << "\ncarrier = \"" << core::name_of<render::SplatCarrier>(render::k_splat_carrier_names, d.carrier) << "\""
      << "\nsplat_shape = \"" << splat_shape_name(d.splat_shape) << "\""
      << "\nsplat_normals = \"" << (d.varying_normals ? "varying" : "flat") << "\""
      << "\nvisibility = \"" << (d.frame.style.mesh_occluders ? "mesh" : "splats") << "\""
      << "\nbackground = " << vec<3>(Vec3f(d.frame.background.head<3>()));
    o << "\npath = \"" << (d.splat_path ? render::splat_path_name(*d.splat_path) : "auto") << "\"\nenvironment = \""
      << render::env_sampling_name(l.environment.sampling) << "\"";
    if (!d.environment_map.empty()) o << "\nenvironment_map = " << toml_string(d.environment_map);
    o << "\nlights = [";
    for (size_t i = 0; i < l.lights.size(); ++i) {
        const render::Light& g = l.lights[i];
        o << (i ? ", " : "") << "{ type = \"" << (g.type == render::LightType::spot ? "spot" : g.type == render::LightType::directional ? "directional" : "point")
          << "\", ";
        write_keys<render::Light>(o, g, k_light_keys, ", ");
        o << " }";
    }
    o << "]\n\n[render.camera]\n";
    // A camera the file did not place stays unplaced, so the models are framed again when read.
    if (d.camera_given) write_keys<render::Camera>(o, c, k_camera_keys);
    else o << "up = " << vec<3>(c.up) << "\nfov_degrees = " << num(c.fov_y_degrees) << "\n";
    o << "orbit_degrees_per_second = " << num(d.orbit.degrees_per_second)
      << "\npath = [";
    for (size_t i = 0; i < d.path.size(); ++i)
        o << (i ? ", " : "") << "{ time = " << num(d.path[i].time) << ", eye = " << vec<3>(d.path[i].eye)
          << ", target = " << vec<3>(d.path[i].target) << " }";
    o << "]"
      << "\n\n[render.light]\n";
    write_keys<render::Lighting>(o, l, k_key_light_keys);
}

void write_events(std::ostream& o, const Scene& sc) {
    for (const Event& e : sc.events) {
        o << "\n[[events]]\ntime = " << num(e.time) << "\ntype = \"" << event_type_name(e.data) << "\"\n";
        if (auto* p = std::get_if<PressureEvent>(&e.data)) {
            o << "value = " << num(p->value) << "\nduration = " << num(p->duration) << "\n";
            if (p->body) o << "body = " << *p->body << "\n";
        }
        if (auto* dr = std::get_if<DragEvent>(&e.data))
            o << "from = " << vec<3>(dr->from) << "\nto = " << vec<3>(dr->to) << "\nduration = " << num(dr->duration)
              << "\nstiffness = " << num(dr->stiffness) << "\nradius = " << num(dr->radius) << "\n";
        if (auto* sp = std::get_if<SpinEvent>(&e.data))
            o << "axis = " << vec<3>(sp->axis) << "\ndegrees_per_second = " << num(sp->degrees_per_second)
              << "\nduration = " << num(sp->duration) << "\n";
        if (auto* cu = std::get_if<CutEvent>(&e.data)) {
            if (cu->segment) o << "from = " << vec<2>((*cu->segment)[0]) << "\nto = " << vec<2>((*cu->segment)[1]) << "\n";
            if (cu->plane) o << "point = " << vec<3>(cu->plane->first) << "\nnormal = " << vec<3>(cu->plane->second) << "\n";
        }
        if (auto* op = std::get_if<OpacityEvent>(&e.data)) o << "value = " << num(op->value) << "\nduration = " << num(op->duration) << "\n";
        if (auto* te = std::get_if<TearEvent>(&e.data)) {
            o << "threshold = " << num(te->threshold) << "\nmax_per_frame = " << te->max_per_frame << "\nduration = " << num(te->duration) << "\n";
            if (te->tip_threshold > 0.0f) o << "tip_threshold = " << num(te->tip_threshold) << "\n";
        }
    }
}

void write_expect(std::ostream& o, const ExpectDesc& e) {
    if (e.empty()) return;
    o << "\n[expect]\n";
    if (e.frames) o << "frames = " << e.frames << "\n";
    for (const bool at_least : {true, false}) {
        std::string line;
        for (const ExpectBound& b : e.bounds)
            if (b.at_least == at_least) line += (line.empty() ? "" : ", ") + b.figure + " = " + num(b.limit);
        if (!line.empty()) o << (at_least ? "at_least" : "at_most") << " = { " << line << " }\n";
    }
}
} // namespace

std::string to_toml(const Scene& sc) {
    std::ostringstream o;
    write_model_material_surface(o, sc);
    write_simulation(o, sc);
    write_render(o, sc);
    write_events(o, sc);
    write_expect(o, sc.expect);
    return o.str();
}

} // namespace pbdsplat::scene
