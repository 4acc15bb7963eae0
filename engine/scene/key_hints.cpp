#include "scene/key_hints.h"

#include <algorithm>
#include <cctype>
#include <vector>

#include "scene/scene_keys.h"

namespace pbdsplat::scene {
namespace {

// Lower case, '-' and ' ' as '_': "Splat-Scale" is plainly splat_scale.
std::string folded(std::string_view s) {
    std::string out(s);
    for (char& c : out) {
        c = char(std::tolower(static_cast<unsigned char>(c)));
        if (c == '-' || c == ' ') c = '_';
    }
    return out;
}

// Edits (insert, delete, substitute, swap two neighbours) from a to b.
size_t edit_distance(std::string_view a, std::string_view b) {
    std::vector<std::vector<size_t>> d(a.size() + 1, std::vector<size_t>(b.size() + 1));
    for (size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
    for (size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
    for (size_t i = 1; i <= a.size(); ++i)
        for (size_t j = 1; j <= b.size(); ++j) {
            d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
        }
    return d[a.size()][b.size()];
}

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
        std::vector<Section> s = {{"model", {"color", "particles", "mass"}},      {"material", {}},      {"surface", {"mode"}},
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
    const std::string k = folded(key);
    // A typo: one edit in a short name, two in a longer one, the nearest first.
    const size_t allowed = k.size() < 5 ? 1 : 2;
    std::string best;
    size_t best_distance = allowed + 1;
    for (const std::string& a : asked) {
        const size_t d = edit_distance(k, a);
        if (d < best_distance) best_distance = d, best = a;
    }
    if (!best.empty()) return " (did you mean '" + best + "'?)";
    // The right name in the wrong table.
    std::string where;
    for (const Section& s : sections()) {
        if (s.path == path) continue;
        if (std::find(s.keys.begin(), s.keys.end(), k) != s.keys.end())
            where += std::string(where.empty() ? "" : " or ") + "[" + s.path + "]";
    }
    return where.empty() ? std::string() : " (a key of " + where + ")";
}

} // namespace pbdsplat::scene
