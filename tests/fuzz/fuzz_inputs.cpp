#include "fuzz/fuzz_inputs.h"

#include <cmath>

#include "asset/obj_loader.h"
#include "scene/scene_file.h"

namespace pbdsplat::fuzz {

namespace {
constexpr const char* k_name = "fuzz-input";
std::string refusal_without_name(const core::Error& e) {
    const std::string m = e.to_string();
    return m.find(k_name) == std::string::npos ? "refused without naming the input: " + m : std::string();
}
} // namespace

std::string check_obj(const std::string& text) {
    auto r = asset::parse_obj(text, k_name);
    if (!r.ok()) return refusal_without_name(r.error());
    const mesh::TriangleMesh& m = r.value();
    for (const Vec3f& p : m.positions)
        if (!p.allFinite()) return "accepted a non-finite position";
    for (const auto& t : m.triangles)
        for (uint32_t i : t)
            if (i >= m.positions.size()) return "accepted an index out of range";
    return {};
}

std::string check_scene(const std::string& text) {
    auto r = scene::parse_scene(text, k_name);
    if (!r.ok()) return refusal_without_name(r.error());
    const scene::Scene& s = r.value();
    if (!(s.simulation.dt > 0.0f) || !std::isfinite(s.simulation.dt)) return "accepted a non-positive or non-finite dt";
    if (s.render.width == 0 || s.render.height == 0) return "accepted an empty image";
    // What was accepted writes back as a scene that reads again.
    auto again = scene::parse_scene(scene::to_toml(s), k_name);
    if (!again.ok()) return "accepted, but its own TOML is refused: " + again.error().to_string();
    return {};
}

} // namespace pbdsplat::fuzz
