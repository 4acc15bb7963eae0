#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <variant>

#include "asset/mesh_spec.h"
#include "mesh/procedural.h"
#include "scene/scene_file.h"
#include "scene/scene_model.h"
#include "support/why.h"

using namespace pbdsplat;

namespace {
std::string refusal(const std::string& text) {
    auto r = scene::parse_scene(text, "bad.toml");
    REQUIRE_FALSE(r.ok());
    return r.error().to_string();
}

constexpr const char* k_full = R"(
[model]
mesh = "torus:32:16"
fit = 0.0
translate = [0.0, 1.0, 0.0]
rotate_degrees = [10.0, 20.0, 30.0]
scale = 0.5
close_holes = true
up = "z"
velocity = [0.5, 0.0, 0.0]
static = true
color = [0.3, 0.6, 0.9]
particles = 0
mass = 2.5
shape_stiffness = 0.4
damping = 0.3
deform_damping = 2.5
pressure = 1.4
stiffness = 0.3
compliance = 2e-4

[[bodies]]
mesh = "box:2"
fit = 1.5
translate = [0.0, 3.0, 0.0]
rotate_degrees = [0.0, 45.0, 0.0]
scale = 0.25
close_holes = true
up = "y"
velocity = [0.0, -1.0, 0.0]
static = true
color = [0.1, 0.2, 0.3]
particles = 300
mass = 0.75
shape_stiffness = 0.2
damping = 0.7
deform_damping = 4
pressure = 0.6
stiffness = 0.05
compliance = 0.01

[material]
color = [0.2, 0.6, 0.9]
opacity = 0.95
shininess = 12
diffuse = 0.8
specular = 0.5
splat_scale = 0.6
interior_color = [0.9, 0.8, 0.5]

[surface]
mode = "vertices"
eta = 0.4
sample_budget = 90000
stretch_scale = true
seed = 7
edge_samples = false
density = false

[advanced]
density_grow = 1.3
density_shrink = 0.8
density_squash = 0.7
density_insert_spacing = 0.8
density_retire_spacing = 0.85
density_settle_frames = 5
density_budget = 77
density_crowd_spacing = 0.6
density_gap_spacing = 0.0

[simulation]
mode = "xpbd"
dt = 0.01
iterations = 2
substeps = 4
stiffness = 0.9
compliance = 1e-4
volume = false
volume_stiffness = 0.8
shape_stiffness = 0.5
shape_compliance = 1e-3
particles = 500
volume_compliance = 1e-5
pressure = 1.2
gravity = [0.0, -5.0, 0.0]
damping = 0.1
deform_damping = 1.5
mass = 2.0
friction = 0.3
static_friction = 0.6
contact = false
contact_thickness = 0.02
contact_substeps = 6
sleep = false
self_contact = true
fold_guard = false
fold_edges = true
weld_parts = false
cut_volume = "burst"
cut_snap = 0.2
fade_frames = 12
pins = [0, 3]
pin_regions = [{ min = [-1, 0.5, -1], max = [1, 2, 1] }]
colliders = [
  { type = "plane", normal = [0, 1, 0], offset = -1.5 },
  { type = "sphere", center = [0.5, -1, 0], radius = 0.25 },
  { type = "box", center = [0, -2, 0], half_extents = [2, 0.1, 2] },
]

[render]
width = 640
height = 360
blend = "normalised"
sort = true
sort_on = "cpu"
shading = "corner"
footprint = "gaussian"
kappa = 2.5
thin_below = 1.5
sharpness = [0.8, 0.9]
carrier = "octagon"
splat_shape = "surfel"
splat_normals = "flat"
surfel_thickness = 0.2
visibility = "mesh"
occluder_tolerance = 2.0
ground = false
cull_back = false
depth_min_alpha = 0.3
depth_push = 1.5
path = "vertex"
environment = "hybrid"
environment_map = "procedural:studio"
environment_intensity = 0.9
environment_diffuse = 0.8
environment_specular = 0.7
lights = [{ type = "point", position = [1, 2, 3], color = [1, 0.9, 0.8], intensity = 2, range = 5 },
          { type = "spot", position = [0, 3, 0], direction = [0, -1, 0], inner_degrees = 10, outer_degrees = 20 }]
background = [0.1, 0.1, 0.1]

[render.camera]
eye = [0, 1, 4]
target = [0, 0.5, 0]
up = [0, 0, 1]
fov_degrees = 50
orbit_degrees_per_second = 20
path = [{ time = 0, eye = [0, 1, 4], target = [0, 0, 0] }, { time = 2.5, eye = [3, 1, 3], target = [0, 0.5, 0] }]

[render.light]
direction = [0, 1, 0]
color = [1, 0.9, 0.9]
intensity = 1.5
ambient = [0.1, 0.1, 0.1]

[[events]]
time = 2.0
type = "pressure"
value = 0.5
duration = 1.0
body = 1

[[events]]
time = 0.5
type = "drag"
from = [0, 1, 0]
to = [0, 2, 0]
duration = 0.5
stiffness = 0.25
radius = 0.3

[[events]]
time = 3.0
type = "cut"
from = [100, 200]
to = [500, 220]

[[events]]
time = 4.0
type = "cut"
point = [0, 0, 0]
normal = [1, 0, 0]

[[events]]
time = 5.0
type = "tear"
threshold = 1.8
tip_threshold = 1.3
max_per_frame = 6
duration = 2.0

[[events]]
time = 1.0
type = "spin"
axis = [0, 1, 0]
degrees_per_second = 90
duration = 0.5

[[events]]
time = 6.0
type = "opacity"
value = 0.5
duration = 1.5

[expect]
frames = 150
at_least = { pieces = 2 }
at_most = { strays_max = 0, shape_error_max = 0.05 }
)";

// to_toml's output as table -> key -> value text, a value's continuation lines joined to it; the
// n-th entry of an array of tables is "events#n", "bodies#n".
using Printed = std::map<std::string, std::map<std::string, std::string>>;
Printed printed_values(const std::string& text) {
    Printed out;
    std::map<std::string, int> entries;
    std::istringstream in(text);
    std::string line, table, key;
    while (std::getline(in, line)) {
        if (line.empty() || line.front() == '#') continue;
        if (line.rfind("[[", 0) == 0) {
            const std::string name = line.substr(2, line.find(']') - 2);
            table = name + "#" + std::to_string(entries[name]++);
            key.clear();
        } else if (line.front() == '[') {
            table = line.substr(1, line.find(']') - 1);
            key.clear();
        } else if (const size_t eq = line.find(" = "); eq != std::string::npos && line.front() != ' ') {
            key = line.substr(0, eq);
            out[table][key] = line.substr(eq + 3);
        } else if (!key.empty()) {
            out[table][key] += "\n" + line;
        }
    }
    return out;
}

// The keys docs/scene-format.md documents, as (table, key): the rows of each `[table]`'s key
// table, and the keys named in the prose of `[render.camera]` and `[render.light]`.
std::vector<std::pair<std::string, std::string>> documented_keys() {
    std::ifstream doc(std::string(PBDSPLAT_PROJECT_SCENES_DIR) + "/../docs/scene-format.md");
    REQUIRE(doc);
    std::vector<std::pair<std::string, std::string>> keys;
    const auto backticked = [](const std::string& text, auto&& each) {
        for (size_t a = text.find('`'); a != std::string::npos;) {
            const size_t b = text.find('`', a + 1);
            if (b == std::string::npos) break;
            each(text.substr(a + 1, b - a - 1));
            a = text.find('`', b + 1);
        }
    };
    // A key named in prose or an event's row: a plain name, each once.
    const auto add_key = [&keys](const std::string& table, const std::string& k) {
        const bool plain = !k.empty() && std::all_of(k.begin(), k.end(), [](char c) { return (c >= 'a' && c <= 'z') || c == '_'; });
        if (plain && std::find(keys.begin(), keys.end(), std::make_pair(table, k)) == keys.end()) keys.emplace_back(table, k);
    };
    std::string line, section, prose;
    while (std::getline(doc, line)) {
        if (line.rfind("## `[[", 0) == 0) section = line.substr(6, line.find(']') - 6);
        else if (line.rfind("## `[", 0) == 0) section = line.substr(5, line.find(']') - 5);
        else if (line.rfind("## ", 0) == 0) section.clear();
        for (const char* sub : {"render.camera", "render.light"})
            if (line.rfind(std::string("`[") + sub + "]`", 0) == 0) prose = sub;
        if (line.empty()) prose.clear();
        if (!prose.empty()) {
            backticked(line.substr(line.find("]`") == std::string::npos ? 0 : line.find("]`") + 2),
                       [&](const std::string& k) { add_key(prose, k); });
            continue;
        }
        if (section.empty() || line.rfind("| `", 0) != 0) continue;
        const size_t cell = line.find('|', 1);
        if (section == "events") {
            // A row per type: the type, then the keys it takes.
            const std::string type = line.substr(3, line.find('`', 3) - 3);
            backticked(line.substr(cell + 1, line.find('|', cell + 1) - cell - 1),
                       [&](const std::string& k) { add_key("events:" + type, k); });
            continue;
        }
        backticked(line.substr(1, cell - 1), [&](const std::string& k) {
            keys.emplace_back(section, k);
            if (section == "model") keys.emplace_back("bodies", k);  // a body takes the [model] keys
        });
    }
    return keys;
}
} // namespace

TEST_SUITE("scene/scene_file") {
    TEST_CASE("every key is read") {
        auto r = scene::parse_scene(k_full, "full.toml");
        REQUIRE_MESSAGE(r.ok(), test::why(r));
        const scene::Scene& s = r.value();
        CHECK(s.name == "full");
        CHECK(s.model.mesh == "torus:32:16");
        CHECK(s.model.scale.axes == Vec3f::Constant(0.5f));
        CHECK(s.simulation.solver.mode == sim::SolverMode::xpbd);
        CHECK(s.simulation.solver.substeps == 4);
        CHECK(s.simulation.pins == std::vector<uint32_t>{0, 3});
        CHECK(s.simulation.colliders.ground.has_value());
        CHECK(s.simulation.colliders.spheres.size() == 1);
        CHECK(s.simulation.colliders.boxes.size() == 1);
        CHECK(s.render.frame.style.blend == render::Blend::normalised);
        CHECK(s.render.orbit.degrees_per_second == 20.0f);
        REQUIRE(s.render.path.size() == 2);
        CHECK(s.render.path[1].eye == Vec3f(3, 1, 3));
        REQUIRE(s.events.size() == 7);
        CHECK(s.events.front().time == 0.5f);  // sorted by time
        CHECK(std::string(scene::event_type_name(s.events.front().data)) == "drag");
        CHECK(s.has_topology_events());
    }

    TEST_CASE("surfels: the shape sets the style's thickness, round and deformed leave it 0") {
        auto surfel = scene::parse_scene("[render]\nsplat_shape = \"surfel\"\nsurfel_thickness = 0.05\n", "s.toml");
        REQUIRE_MESSAGE(surfel.ok(), test::why(surfel));
        CHECK(surfel->render.splat_shape == scene::SplatShape::surfel);
        CHECK(surfel->render.frame.style.surfel_thickness == 0.05f);
        auto round = scene::parse_scene("[render]\nsurfel_thickness = 0.05\n", "r.toml");
        REQUIRE(round.ok());
        CHECK(round->render.frame.style.surfel_thickness == 0.0f);
        auto bad = scene::parse_scene("[render]\nsplat_shape = \"surfel\"\nsurfel_thickness = 0\n", "b.toml");
        REQUIRE_FALSE(bad.ok());
        CHECK(bad.error().to_string().find("surfel_thickness") != std::string::npos);
        auto unknown = scene::parse_scene("[render]\nsplat_shape = \"flat\"\n", "u.toml");
        REQUIRE_FALSE(unknown.ok());
        CHECK(unknown.error().to_string().find("surfel") != std::string::npos);  // the accepted names are listed
    }

    TEST_CASE("normalised blending needs the Gaussian footprint, and says so with the line") {
        auto ok = scene::parse_scene("[render]\nfootprint = \"gaussian\"\nblend = \"normalised\"\n", "n.toml");
        REQUIRE_MESSAGE(ok.ok(), test::why(ok));
        CHECK(ok->render.frame.style.blend == render::Blend::normalised);
        auto again = scene::parse_scene(scene::to_toml(ok.value()), "printed.toml");
        REQUIRE_MESSAGE(again.ok(), test::why(again));
        CHECK(again->render.frame.style.blend == render::Blend::normalised);
        // The paper's disc is the default footprint: it has no falloff to weigh by.
        const std::string why = refusal("[render]\nblend = \"normalised\"\n");
        CHECK(why.find("bad.toml:2:9: 'render.blend' = \"normalised\"") == 0);
        CHECK(why.find("footprint") != std::string::npos);
    }

    TEST_CASE("mesh occluders serve normalised blending, print back, and say so with the line") {
        auto ok = scene::parse_scene("[render]\nfootprint = \"gaussian\"\nblend = \"normalised\"\nvisibility = \"mesh\"\n"
                                     "occluder_tolerance = 2.5\n", "m.toml");
        REQUIRE_MESSAGE(ok.ok(), test::why(ok));
        CHECK(ok->render.frame.style.mesh_occluders);
        CHECK(ok->render.occluder_tolerance == doctest::Approx(2.5f));
        auto again = scene::parse_scene(scene::to_toml(ok.value()), "printed.toml");
        REQUIRE_MESSAGE(again.ok(), test::why(again));
        CHECK(again->render.frame.style.mesh_occluders);
        CHECK(again->render.occluder_tolerance == doctest::Approx(2.5f));
        // The default: the mesh under normalised blending, the splats' own cores otherwise.
        auto plain = scene::parse_scene("[render]\nfootprint = \"gaussian\"\nblend = \"normalised\"\n", "p.toml");
        REQUIRE(plain.ok());
        CHECK(plain->render.frame.style.mesh_occluders);
        auto cores = scene::parse_scene("[render]\nfootprint = \"gaussian\"\nblend = \"normalised\"\nvisibility = \"splats\"\n", "c.toml");
        REQUIRE(cores.ok());
        CHECK_FALSE(cores->render.frame.style.mesh_occluders);
        auto over = scene::parse_scene("[render]\nfootprint = \"gaussian\"\n", "o.toml");
        REQUIRE(over.ok());
        CHECK_FALSE(over->render.frame.style.mesh_occluders);
        auto again_cores = scene::parse_scene(scene::to_toml(cores.value()), "printed_cores.toml");
        REQUIRE(again_cores.ok());
        CHECK_FALSE(again_cores->render.frame.style.mesh_occluders);
        // The paper's disc under "over" (the defaults) takes them too; the Gaussian under "over"
        // and additive blending do not.
        auto paper = scene::parse_scene("[render]\nvisibility = \"mesh\"\n", "d.toml");
        REQUIRE_MESSAGE(paper.ok(), test::why(paper));
        CHECK(paper->render.frame.style.mesh_occluders);
        const std::string why = refusal("[render]\nfootprint = \"gaussian\"\nvisibility = \"mesh\"\n");
        CHECK(why.find("bad.toml:3:14: 'render.visibility' = \"mesh\"") == 0);
        CHECK(why.find("normalised") != std::string::npos);
        CHECK(refusal("[render]\nblend = \"additive\"\nvisibility = \"mesh\"\n").find("bad.toml:3:14:") == 0);
        CHECK(refusal("[render]\nvisibility = \"cores\"\n").find("must be one of splats, mesh") != std::string::npos);
        CHECK(refusal("[render]\noccluder_tolerance = 0.0\n").find("occluder_tolerance") != std::string::npos);
    }

    TEST_CASE("a scene survives printing and parsing again") {
        auto first = scene::parse_scene(k_full, "full.toml");
        REQUIRE(first.ok());
        const std::string printed = scene::to_toml(first.value());
        auto second = scene::parse_scene(printed, "printed.toml");
        REQUIRE_MESSAGE(second.ok(), test::why(second) << "\n" << printed);
        CHECK(scene::to_toml(second.value()) == printed);
        CHECK(second->simulation.colliders.spheres[0].radius == first->simulation.colliders.spheres[0].radius);
        // The values that are not the defaults come back as they were set.
        CHECK(second->render.frame.style.footprint == render::Footprint::gaussian);
        REQUIRE(second->material.interior_color.has_value());
        CHECK(second->material.interior_color->isApprox(Vec3f(0.9f, 0.8f, 0.5f)));
        CHECK(second->render.frame.style.sharpness == Vec2f(0.8f, 0.9f));
        CHECK(second->render.carrier == render::SplatCarrier::octagon);
        CHECK(second->surface.density.grow == doctest::Approx(1.3f));
        CHECK(second->surface.density.budget == 77u);
        CHECK(second->surface.density.gap_spacing == 0.0f);
        CHECK(second->render.splat_shape == scene::SplatShape::surfel);
        CHECK(second->render.surfel_thickness == 0.2f);
        CHECK(second->render.frame.style.surfel_thickness == 0.2f);  // surfels take the thickness
        CHECK(second->expect.frames == 150);
        CHECK(second->simulation.solver.contact.substeps == 6);
        const auto tear = std::find_if(second->events.begin(), second->events.end(),
                                       [](const scene::Event& e) { return std::holds_alternative<scene::TearEvent>(e.data); });
        REQUIRE(tear != second->events.end());
        CHECK(std::get<scene::TearEvent>(tear->data).tip_threshold == 1.3f);
        REQUIRE(second->expect.bounds.size() == 3);
        const auto bound = [&](const char* figure) {
            for (const scene::ExpectBound& b : second->expect.bounds)
                if (b.figure == figure) return b;
            FAIL("no bound on " << figure);
            return scene::ExpectBound{};
        };
        CHECK(bound("pieces").at_least);
        CHECK(bound("pieces").limit == 2.0);
        CHECK_FALSE(bound("shape_error_max").at_least);
        CHECK(bound("shape_error_max").limit == doctest::Approx(0.05));
        CHECK_FALSE(second->render.ground);
        CHECK_FALSE(second->render.cull_back);
        CHECK(second->events.size() == first->events.size());
    }

    TEST_CASE("every key docs/scene-format.md documents is set by the full scene to other than its default, printed, and read back as set") {
        // Not the printer against itself: the documented keys, read from the format's own page.
        // A key the fixture left at its default would come back as the default even if the
        // reader dropped it, so each must differ from the default scene's; and each must print
        // the same after a second parse, so a key the printer or the reader loses fails here.
        auto full = scene::parse_scene(k_full, "full.toml");
        REQUIRE_MESSAGE(full.ok(), test::why(full));
        auto defaults = scene::parse_scene("", "empty.toml");
        REQUIRE_MESSAGE(defaults.ok(), test::why(defaults));
        const std::string printed = scene::to_toml(full.value());
        auto again = scene::parse_scene(printed, "printed.toml");
        REQUIRE_MESSAGE(again.ok(), test::why(again) << "\n" << printed);
        const Printed set = printed_values(printed), plain = printed_values(scene::to_toml(defaults.value())),
                      back = printed_values(scene::to_toml(again.value()));
        // An array table's entry is held against one that sets only what it must: a body its
        // mesh, an event the keys it cannot go without (those are not checked for defaults).
        const std::map<std::string, std::string> least = {
            {"bodies", "mesh = \"icosphere:1\""},
            {"pressure", "value = 0.5"},
            {"drag", "from = [0, 1, 0]\nto = [0, 2, 0]"},
            {"spin", "axis = [0, 1, 0]\ndegrees_per_second = 90"},
            {"cut", "from = [100, 200]\nto = [500, 220]"},  // or a plane: 'point' and 'normal', as required
            {"opacity", "value = 0.5"},
            {"tear", ""},
        };
        // Each such entry as printed, made once per kind.
        std::map<std::string, Printed> least_printed;
        for (const auto& [kind, text] : least) {
            auto one = scene::parse_scene(kind == "bodies" ? "[[bodies]]\n" + text + "\n"
                                                           : "[[events]]\ntime = 1\ntype = \"" + kind + "\"\n" + text + "\n",
                                          "least.toml");
            REQUIRE_MESSAGE(one.ok(), test::why(one));
            least_printed[kind] = printed_values(scene::to_toml(one.value()));
        }
        // The tables of `p` that hold `table`'s keys: itself, or the array entries of its kind.
        const auto entries = [](const Printed& p, const std::string& table) {
            std::vector<const std::map<std::string, std::string>*> out;
            const bool event = table.rfind("events:", 0) == 0;
            for (const auto& [name, values] : p) {
                if (name == table) out.push_back(&values);
                if (!event && name == table + "#0") out.push_back(&values);
                auto type = values.find("type");
                if (event && name.rfind("events#", 0) == 0 && type != values.end() && type->second == "\"" + table.substr(7) + "\"")
                    out.push_back(&values);
            }
            return out;
        };
        size_t checked = 0;
        for (const auto& [table, key] : documented_keys()) {
            CAPTURE(table);
            CAPTURE(key);
            const std::string kind = table.rfind("events:", 0) == 0 ? table.substr(7) : table;
            const Printed& defaults_printed = least.count(kind) ? least_printed.at(kind) : plain;
            const bool required = kind == "cut" || (least.count(kind) && kind != "bodies" && least.at(kind).find(key + " = ") != std::string::npos);
            // Set somewhere other than its default, and every entry reads back as printed.
            bool printed_somewhere = false, differs_somewhere = required;
            const auto fulls = entries(set, table), backs = entries(back, table), plains = entries(defaults_printed, table);
            REQUIRE(fulls.size() == backs.size());
            for (size_t i = 0; i < fulls.size(); ++i) {
                auto v = fulls[i]->find(key);
                if (v == fulls[i]->end()) continue;
                printed_somewhere = true;
                const std::string* plain_value = nullptr;
                for (const auto* pl : plains)
                    if (auto pv = pl->find(key); pv != pl->end()) plain_value = &pv->second;
                differs_somewhere |= !plain_value || *plain_value != v->second;
                auto b = backs[i]->find(key);
                CHECK_MESSAGE((b != backs[i]->end() && b->second == v->second),
                              "[" << table << "] " << key << " = " << v->second << " read back as " << (b != backs[i]->end() ? b->second : "nothing"));
            }
            if (!printed_somewhere) {
                FAIL_CHECK("[" << table << "] " << key << " is documented but to_toml does not print it from the full scene");
                continue;
            }
            CHECK_MESSAGE(differs_somewhere, "[" << table << "] " << key << " prints as its default: the full scene leaves it so (set it in k_full), or the reader drops it");
            ++checked;
        }
        MESSAGE(checked << " documented keys set, printed and read back");
        CHECK(checked > 120);
    }

    TEST_CASE("malformed scenes are refused with file, line and column") {
        CHECK(refusal("[model]\nmesh = \"icosphere:3\"\ncolour = 1\n") == "bad.toml:3:1: unknown key 'model.colour' (did you mean 'color'?)");
        CHECK(refusal("[simulation]\niterations = \"five\"\n") == "bad.toml:2:14: 'simulation.iterations' must be a whole number");
        CHECK(refusal("[simulation]\n  dt = 2.0\n") == "bad.toml:2:8: 'simulation.dt' = 2 is out of range [0.001, 0.1]");
        CHECK(refusal("[render]\nblend = \"multiply\"\n") == "bad.toml:2:9: 'render.blend' must be one of over, additive, normalised, not 'multiply'");
        CHECK(refusal("[material]\ncolor = [1, 0]\n") == "bad.toml:2:9: 'material.color' must be an array of 3 numbers");
        CHECK(refusal("[[events]]\ntime = 1\ntype = \"cut\"\n").find("bad.toml:1:1: a cut event needs either") == 0);
        // A procedural mesh's parameters are read with the file, so the refusal has its line.
        CHECK(refusal("[model]\nmesh = \"icosphere:-1\"\n") == "bad.toml:2:8: mesh 'icosphere:-1': '-1' must be a whole number from 0 to 8");
        CHECK(refusal("[model]\nmesh = \"box:1\"\n[[bodies]]\nmesh = \"torus:12\"\n") == "bad.toml:4:8: mesh 'torus:12': torus takes 2 parameter(s)");
        CHECK(scene::parse_scene("[model]\nmesh = \"uvsphere:8:16\"\n", "good.toml").ok());
        // A half-specified event is an error, not a silent no-op.
        CHECK(refusal("[[events]]\ntime = 1\ntype = \"pressure\"\n") ==
              "bad.toml:1:1: a pressure event needs 'value' (the pressure factor k to reach, 0.01 to 100)");
        CHECK(refusal("[[events]]\ntime = 1\ntype = \"spin\"\naxis = [0, 1, 0]\n") ==
              "bad.toml:1:1: a spin event needs 'axis' ([x, y, z]) and 'degrees_per_second'");
        CHECK(refusal("[[events]]\ntime = 1\ntype = \"cut\"\nfrom = [10, 10]\n") ==
              "bad.toml:1:1: a cut along a screen segment needs both 'from' and 'to' (pixels)");
        CHECK(refusal("[[events]]\ntime = 1\ntype = \"cut\"\npoint = [0, 0, 0]\n") ==
              "bad.toml:1:1: a cut by a plane needs both 'point' and 'normal'");
        CHECK(refusal("[[events]]\ntime = 1\ntype = \"explode\"\n") ==
              "bad.toml:3:8: 'events.type' must be one of pressure, drag, spin, cut, tear, opacity, not 'explode'");
        CHECK(refusal("[model\nmesh = 1\n").find("bad.toml:1:") == 0);  // truncated table header
        // The density control's internals live in [advanced]; where they used to be, a pointer.
        CHECK(refusal("[surface]\ndensity_grow = 1.2\n") ==
              "bad.toml:2:16: 'surface.density_grow' is one of the density control's internals: it belongs in the [advanced] table");
        CHECK(refusal("frames = 10\n") == "bad.toml:1:1: unknown key 'frames' (a key of [expect])");
        CHECK(refusal("[render.camera]\npath = [{ time = 2, eye = [0, 0, 3] }, { time = 1, eye = [0, 0, 4] }]\n")
                  .find("bad.toml:2:40: camera path keys must be in increasing time") == 0);
    }

    TEST_CASE("an unknown key says what was probably meant") {
        // A near spelling of a key its own table reads: case, dashes, a letter dropped or swapped.
        CHECK(refusal("[simulation]\niteration = 5\n") == "bad.toml:2:1: unknown key 'simulation.iteration' (did you mean 'iterations'?)");
        CHECK(refusal("[material]\nSplat-Scale = 1\n") == "bad.toml:2:1: unknown key 'material.Splat-Scale' (did you mean 'splat_scale'?)");
        CHECK(refusal("[simulation]\ngarvity = [0, 0, 0]\n").find("(did you mean 'gravity'?)") != std::string::npos);
        CHECK(refusal("[[events]]\ntime = 1\ntype = \"drag\"\nfrom = [0, 0, 0]\nto = [0, 1, 0]\nduraton = 2\n")
                  .find("unknown key 'events.duraton' (did you mean 'duration'?)") != std::string::npos);
        // The right name in the wrong table.
        CHECK(refusal("[[colliders]]\ntype = \"sphere\"\n") == "bad.toml:1:3: unknown key 'colliders' (a key of [simulation])");
        CHECK(refusal("[simulation]\neta = 0.5\n") == "bad.toml:2:1: unknown key 'simulation.eta' (a key of [surface])");
        CHECK(refusal("[render]\nfriction = 1\n") == "bad.toml:2:1: unknown key 'render.friction' (a key of [simulation])");
        // A value's near spelling, as a key's.
        CHECK(refusal("[render]\nblend = \"normalized\"\n") ==
              "bad.toml:2:9: 'render.blend' must be one of over, additive, normalised, not 'normalized' (did you mean 'normalised'?)");
        // Nothing near: no guess.
        CHECK(refusal("[render]\nwobble = 1\n") == "bad.toml:2:1: unknown key 'render.wobble'");
    }

    TEST_CASE("every scene in scenes/ validates, and states what it shows in an [expect] table over a timeline") {
        size_t n = 0;
        for (const auto& entry : std::filesystem::directory_iterator(PBDSPLAT_SCENES_DIR)) {
            if (entry.path().extension() != ".toml") continue;
            auto r = scene::load_scene(entry.path().string());
            REQUIRE_MESSAGE(r.ok(), test::why(r));
            CHECK_MESSAGE(!r->expect.bounds.empty(), entry.path().string() << ": no [expect] bounds");
            // The run covers every event and half a second after the last one ends.
            double end = 0.0;
            for (const scene::Event& e : r->events) {
                double duration = 0.0;
                std::visit([&](const auto& d) {
                    if constexpr (requires { d.duration; }) duration = d.duration;
                }, e.data);
                end = std::max(end, double(e.time) + duration);
            }
            const double run = r->expect.frames * double(r->simulation.dt);
            CHECK_MESSAGE(run >= end + 0.5, entry.path().string() << ": [expect] frames cover " << run << " s, its events end at " << end << " s");
            ++n;
        }
        CHECK(n >= 1);
    }

    TEST_CASE("[expect]: read, printed and read again bound by bound; a figure check does not measure is refused with its line") {
        const char* text = "[expect]\nframes = 240\nat_least = { pieces = 3, iou_min = 0.84 }\nat_most = { strays_max = 0, hole_ratio_max = 0.0075 }\n";
        auto a = scene::parse_scene(text, "e.toml");
        REQUIRE_MESSAGE(a.ok(), test::why(a));
        CHECK(a->expect.frames == 240);
        REQUIRE(a->expect.bounds.size() == 4);
        auto b = scene::parse_scene(scene::to_toml(a.value()), "again.toml");
        REQUIRE_MESSAGE(b.ok(), test::why(b));
        CHECK(b->expect.frames == 240);
        REQUIRE(b->expect.bounds.size() == a->expect.bounds.size());
        for (size_t i = 0; i < a->expect.bounds.size(); ++i) {
            CHECK(b->expect.bounds[i].figure == a->expect.bounds[i].figure);
            CHECK(b->expect.bounds[i].at_least == a->expect.bounds[i].at_least);
            CHECK(b->expect.bounds[i].limit == doctest::Approx(a->expect.bounds[i].limit));
        }
        CHECK(refusal("[expect]\nat_least = { pieces = 2, peices = 3 }\n").find("bad.toml:2:26: 'expect.at_least.peices' is not a figure") == 0);
        CHECK(refusal("[expect]\nframes = 0\n").find("bad.toml:2:10: 'expect.frames' = 0 is out of range") == 0);
        CHECK(refusal("[expect]\nat_most = { pieces = \"two\" }\n").find("'expect.at_most.pieces' must be a number") != std::string::npos);
        CHECK(refusal("[expect]\nwithin = { pieces = 2 }\n").find("unknown key 'expect.within'") != std::string::npos);
    }

    TEST_CASE("a procedural mesh of a few vertices is subdivided flat: a box of one division stays a box, in splats smaller than its faces") {
        auto scene = scene::parse_scene("[model]\nmesh = \"box:1\"\n", "box1.toml");
        REQUIRE_MESSAGE(scene.ok(), test::why(scene));
        auto model = scene::load_scene_model(scene.value());
        REQUIRE_MESSAGE(model.ok(), test::why(model));
        const sim::SoftBody& b = model.value().body;
        CHECK(b.particle_count() >= asset::k_min_procedural_vertices);  // 8 as given: every splat spanned a face
        Vec3f lo = Vec3f::Constant(1e9f), hi = -lo;
        for (const Vec4f& x : b.particles.x) lo = lo.cwiseMin(x.head<3>()), hi = hi.cwiseMax(x.head<3>());
        const mesh::TriangleMesh given = mesh::box(Vec3f::Constant(1.0f), 1);
        Vec3f glo = Vec3f::Constant(1e9f), ghi = -glo;
        for (const Vec3f& x : given.positions) glo = glo.cwiseMin(x), ghi = ghi.cwiseMax(x);
        CHECK(lo.isApprox(glo, 1e-5f));  // measured: flat subdivision moves no corner
        CHECK(hi.isApprox(ghi, 1e-5f));
        // The resolution a user gives above the floor is kept.
        auto four = scene::load_scene_model(scene::parse_scene("[model]\nmesh = \"box:4\"\n", "box4.toml").value());
        REQUIRE_MESSAGE(four.ok(), test::why(four));
        CHECK(four.value().body.particle_count() == 6 * 4 * 4 + 2);  // a cube's surface of 4 x 4 quads a face
    }

    TEST_CASE("substeps left out of the file are raised for a solid too small to stand at one, and only then") {
        const auto substeps = [](const std::string& text) {
            auto scene = scene::parse_scene(text, "small.toml");
            REQUIRE_MESSAGE(scene.ok(), test::why(scene));
            auto model = scene::load_scene_model(scene.value());
            REQUIRE_MESSAGE(model.ok(), test::why(model));
            return model.value().substeps;
        };
        const std::string ground = "colliders = [{ type = \"plane\", normal = [0, 1, 0], offset = -0.5 }]\n";
        const std::string small = "[model]\nmesh = \"quadruped:4\"\nscale = 0.1\n[simulation]\n";
        // A 0.2 m quadruped: gravity's frame is 0.67 of its mean edge, so 7 substeps keep it to a
        // tenth (it tips onto its side at one: tests/scenes/rest_small_quadruped.toml).
        CHECK(substeps(small + ground) == 7);
        CHECK(substeps(small + ground + "substeps = 2\n") == 2);   // the file's choice stands
        CHECK(substeps(small + ground + "shape_stiffness = 0\n") == 1);  // a balloon does not stand
        CHECK(substeps(small) == 1);                                 // nothing to stand on
        CHECK(substeps("[model]\nmesh = \"quadruped:4\"\n[simulation]\n" + ground) == 1);  // at 2 m: 0.07
        // Written back, substeps the file left out stay out (and chosen again on loading).
        auto scene = scene::parse_scene(small + ground, "small.toml");
        REQUIRE(scene.ok());
        CHECK(scene::to_toml(scene.value()).find("\nsubsteps =") == std::string::npos);
        CHECK(scene::to_toml(scene::parse_scene(small + ground + "substeps = 3\n", "s.toml").value()).find("\nsubsteps = 3\n") != std::string::npos);
    }

    TEST_CASE("[[bodies]]: read, printed and read again field by field; each model its own piece, static ones pinned") {
        const char* text = R"(
[model]
mesh = "box:2"
[[bodies]]
mesh = "icosphere:1"
translate = [0, 2, 0]
velocity = [1, -2, 0.5]
color = [0.1, 0.2, 0.3]
[[bodies]]
mesh = "icosphere:2"
translate = [3, 0, 0]
scale = [0.5, 0.25, 1.0]
static = true
particles = 0
)";
        auto first = scene::parse_scene(text, "bodies.toml");
        REQUIRE_MESSAGE(first.ok(), test::why(first));
        auto again = scene::parse_scene(scene::to_toml(first.value()), "again.toml");
        REQUIRE_MESSAGE(again.ok(), test::why(again));
        for (const scene::Scene* sc : {&first.value(), &again.value()}) {
            REQUIRE(sc->bodies.size() == 2);
            CHECK(sc->bodies[0].model.mesh == "icosphere:1");
            CHECK(sc->bodies[0].model.translate.isApprox(Vec3f(0, 2, 0)));
            CHECK(sc->bodies[0].model.velocity.isApprox(Vec3f(1, -2, 0.5f)));
            REQUIRE(sc->bodies[0].own.color);
            CHECK(sc->bodies[0].own.color->isApprox(Vec3f(0.1f, 0.2f, 0.3f)));
            CHECK_FALSE(sc->bodies[0].model.fixed);
            CHECK(sc->bodies[1].model.fixed);
            CHECK(sc->bodies[1].model.scale.axes.isApprox(Vec3f(0.5f, 0.25f, 1.0f)));
            REQUIRE(sc->bodies[1].own.particles);
            CHECK(*sc->bodies[1].own.particles == 0);
        }
        auto model = scene::load_scene_model(first.value());
        REQUIRE_MESSAGE(model.ok(), test::why(model));
        const sim::SoftBody& b = model.value().body;
        CHECK(b.pieces == 3);
        const std::vector<uint32_t>& start = model.value().part_start;
        REQUIRE(start.size() == 4);
        for (uint32_t i = start[1]; i < start[2]; ++i) {
            CHECK(b.particles.v[i].head<3>().isApprox(Vec3f(1, -2, 0.5f)));
            CHECK(b.colors[i].isApprox(Vec3f(0.1f, 0.2f, 0.3f)));
            CHECK(b.particles.x[i].y() > 0.99f);  // placed where its entry says (a unit ball raised by 2)
        }
        for (uint32_t i = start[2]; i < start[3]; ++i) CHECK(b.particles.w[i] == 0.0f);
        // Scaled per axis in its own frame: the unit ball's diameters become 1, 0.5 and 2.
        Vec3f lo = Vec3f::Constant(1e9f), hi = -lo;
        for (uint32_t i = start[2]; i < start[3]; ++i) lo = lo.cwiseMin(b.particles.x[i].head<3>()), hi = hi.cwiseMax(b.particles.x[i].head<3>());
        CHECK((hi - lo).isApprox(Vec3f(1.0f, 0.5f, 2.0f), 1e-4f));  // measured: the vertices lie on the unit sphere's axes
        CHECK(((hi + lo) * 0.5f).isApprox(Vec3f(3, 0, 0), 1e-4f));
        for (uint32_t i = start[0]; i < start[1]; ++i) CHECK(b.particles.w[i] > 0.0f);
        CHECK_FALSE(scene::parse_scene("[[bodies]]\ntranslate = [0, 1, 0]\n", "nomesh.toml").ok());
        // A model that cannot load is named as the file numbers it: here its third [[bodies]]
        // entry, the first being the scene's model (no [model] table).
        for (const bool with_model : {false, true}) {
            const std::string bodies = std::string(with_model ? "[model]\nmesh = \"box:2\"\n" : "") +
                                       "[[bodies]]\nmesh = \"box:2\"\n[[bodies]]\nmesh = \"box:2\"\n[[bodies]]\nmesh = \"no-such-model.obj\"\n";
            auto missing = scene::parse_scene(bodies, "missing.toml");
            REQUIRE_MESSAGE(missing.ok(), test::why(missing));
            auto loaded = scene::load_scene_model(missing.value());
            REQUIRE_FALSE(loaded.ok());
            CHECK(loaded.error().to_string().find("bodies[2] (no-such-model.obj): ") != std::string::npos);
        }
        const auto refusal = [](const char* t) { return scene::parse_scene(t, "bad.toml").error().to_string(); };
        CHECK(refusal("[model]\nscale = [1, 2]\n").find("bad.toml:2:9: 'model.scale' must be a number or an array of 3 numbers") == 0);
        CHECK(refusal("[model]\nscale = \"big\"\n").find("'model.scale' must be a number or an array of 3 numbers") != std::string::npos);
        CHECK(refusal("[model]\nscale = [1, 0, 1]\n").find("'model.scale' element 0 is out of range") != std::string::npos);
    }

    TEST_CASE("a model's up axis is read, written back and refused by name") {
        auto sc = scene::parse_scene("[model]\nmesh = \"part.stl\"\nup = \"y\"\n[[bodies]]\nmesh = \"box:2\"\nup = \"z\"\n", "up.toml");
        REQUIRE_MESSAGE(sc.ok(), test::why(sc));
        CHECK(sc->model.up == asset::UpAxis::y);
        CHECK(sc->bodies.at(0).model.up == asset::UpAxis::z);
        auto again = scene::parse_scene(scene::to_toml(sc.value()), "printed.toml");
        REQUIRE_MESSAGE(again.ok(), test::why(again));
        CHECK(again->model.up == asset::UpAxis::y);
        CHECK(again->bodies.at(0).model.up == asset::UpAxis::z);
        auto plain = scene::parse_scene("[model]\nmesh = \"part.stl\"\n", "plain.toml");
        REQUIRE(plain.ok());
        CHECK(plain->model.up == asset::UpAxis::file_default);
        CHECK(scene::to_toml(plain.value()).find("\nup = \"") == std::string::npos);  // the camera has an up of its own
        CHECK(refusal("[model]\nmesh = \"part.stl\"\nup = \"x\"\n") == "bad.toml:3:6: 'model.up' must be one of auto, y, z, not 'x'");
    }

    TEST_CASE("[model] takes 'static' and 'velocity' as a [[bodies]] entry does: a table written first holds still") {
        const char* table_first = R"(
[model]
mesh = "box:4"
scale = [2.0, 0.1, 1.2]
static = true
[[bodies]]
mesh = "icosphere:2"
translate = [0, 1, 0]
velocity = [0, -1, 0]
)";
        auto sc = scene::parse_scene(table_first, "table_first.toml");
        REQUIRE_MESSAGE(sc.ok(), test::why(sc));
        CHECK(sc->model.fixed);
        auto model = scene::load_scene_model(sc.value());
        REQUIRE_MESSAGE(model.ok(), test::why(model));
        const sim::SoftBody& b = model.value().body;
        const std::vector<uint32_t>& start = model.value().part_start;
        REQUIRE(start.size() == 3);
        for (uint32_t i = start[0]; i < start[1]; ++i) CHECK(b.particles.w[i] == 0.0f);
        for (uint32_t i = start[1]; i < start[2]; ++i) CHECK(b.particles.v[i].y() == doctest::Approx(-1.0f));
        // A model alone, thrown.
        auto thrown = scene::parse_scene("[model]\nmesh = \"icosphere:2\"\nvelocity = [2, 0, 0]\n", "thrown.toml");
        REQUIRE(thrown.ok());
        auto alone = scene::load_scene_model(thrown.value());
        REQUIRE_MESSAGE(alone.ok(), test::why(alone));
        for (size_t i = 0; i < alone.value().body.particle_count(); ++i) CHECK(alone.value().body.particles.v[i].x() == doctest::Approx(2.0f));
    }
}
