#include "scene/key_hints.h"

#include <algorithm>
#include <vector>

#include "core/spelling.h"

#include "scene/scene_keys.h"

namespace pbdsplat::scene {
namespace {

struct Section {
    const char* path;
    std::vector<std::string> keys;
};

template <class D, size_t N>
void add_keys(std::vector<std::string>& out, const keys::Key<D> (&table)[N]) {
    for (const auto& k : table) out.emplace_back(k.name);
}

// The sections and the keys each reads: the plain keys from scene_keys.h, the rest read by hand
// in scene_file.cpp.
const std::vector<Section>& sections() {
    static const std::vector<Section> all = [] {
        std::vector<Section> s = {{"model", {"color", "particles", "mass", "shape_stiffness", "damping", "deform_damping", "pressure", "stiffness", "compliance"}},      {"material", {}},      {"surface", {"mode"}},
                                  {"advanced", {}},   {"simulation", {"mode", "particles", "cut_volume", "pins", "pin_regions", "colliders"}},
                                  {"render", {"blend", "sort_on", "shading", "splat_shape", "splat_normals", "visibility", "path",
                                              "environment_map", "camera", "light", "lights"}},
                                  {"render.camera", {"path"}}, {"render.light", {}}, {"expect", {"frames", "at_least", "at_most"}}};
        add_keys(s[0].keys, keys::k_model_keys);
        add_keys(s[1].keys, keys::k_material_keys);
        add_keys(s[2].keys, keys::k_surface_keys);
        add_keys(s[3].keys, keys::k_advanced_keys);
        add_keys(s[4].keys, keys::k_simulation_keys);
        add_keys(s[5].keys, keys::k_render_keys);
        add_keys(s[6].keys, keys::k_camera_keys);
        add_keys(s[7].keys, keys::k_key_light_keys);
        return s;
    }();
    return all;
}

} // namespace

std::string unknown_key_hint(std::string_view key, const std::set<std::string>& asked, std::string_view path) {
    const std::vector<std::string> known(asked.begin(), asked.end());
    if (const auto near = core::nearest_spelling(key, known)) return " (did you mean '" + *near + "'?)";
    // The right name in the wrong table.
    std::string where;
    for (const Section& s : sections()) {
        if (s.path == path) continue;
        if (std::find(s.keys.begin(), s.keys.end(), key) != s.keys.end())
            where += std::string(where.empty() ? "" : " or ") + "[" + s.path + "]";
    }
    return where.empty() ? std::string() : " (a key of " + where + ")";
}

} // namespace pbdsplat::scene
