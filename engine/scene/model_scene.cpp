#include "scene/model_scene.h"

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "asset/file_kind.h"
#include "asset/mesh_spec.h"
#include "asset/model_file.h"
#include "scene/framing.h"
#include "scene/scene_file.h"

namespace pbdsplat::scene {

core::Result<InputKind> input_kind(const std::string& path) {
    auto kind = asset::sniff_file(path);
    if (!kind.ok()) return kind.error();
    if (kind.value() == asset::FileKind::scene) return InputKind::scene;
    if (kind.value() == asset::FileKind::ply_gaussians) return InputKind::gaussians;
    return InputKind::model;
}

namespace {

std::string quoted(const std::string& s) {
    std::string out = "\"";
    for (char c : s) {
        if (c == '"' || c == '\\') out += '\\';
        out += c;
    }
    return out + "\"";
}

std::string number(float v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4g", std::abs(v) < 1e-5f ? 0.0 : double(v));
    return buf;
}

std::string vec(const Vec3f& v) { return "[" + number(v.x()) + ", " + number(v.y()) + ", " + number(v.z()) + "]"; }

} // namespace

core::Result<std::string> model_scene_text(const std::string& model_path, const std::string& mesh_as) {
    const ModelDesc defaults;
    asset::MeshSpecOptions o;
    o.file_fit_diagonal = defaults.fit;
    auto model = asset::load_model(model_path, o);
    if (!model.ok()) return model.error();
    const mesh::Bounds b = mesh::bounds(model.value().repaired.mesh);
    // The ground a hair under the lowest point, so the model starts resting, not falling.
    const float ground = b.min.y() - 0.002f * b.diagonal();
    // Framed with the default lens, whichever side the orbit shows.
    const render::Camera camera = framing_camera(b, render::Camera{}, 16.0f / 9.0f);
    const std::string name = std::filesystem::path(model_path).filename().string();
    std::string t;
    t += "# The scene pbdsplat made for " + name + ": the model resting on the ground under the default\n";
    t += "# material and settings, the camera orbiting it. Edit and run it as any scene.\n\n";
    t += "[model]\nmesh = " + quoted(mesh_as.empty() ? model_path : mesh_as) + "\n\n";
    t += "[simulation]\ncolliders = [{ type = \"plane\", normal = [0, 1, 0], offset = " + number(ground) + " }]\n\n";
    t += "[render]\n# Normalised blending of surfels: the look of the shipped scenes (docs/scene-format.md).\n";
    t += "footprint = \"gaussian\"\nblend = \"normalised\"\nkappa = 2.0\nsplat_shape = \"surfel\"\n\n";
    t += "[render.camera]\neye = " + vec(camera.eye) + "\ntarget = " + vec(camera.target) + "\norbit_degrees_per_second = 15.0\n";
    return t;
}

core::Result<Scene> scene_for_model(const std::string& model_path) {
    auto text = model_scene_text(model_path);
    if (!text.ok()) return text.error();
    auto s = parse_scene(text.value(), model_path + " (its default scene)");
    if (!s.ok()) return s.error();
    s->name = std::filesystem::path(model_path).stem().string();
    s->source_dir.clear();  // the model path is the user's, relative to where they stand
    return s;
}

core::Result<ModelSummary> summarize_model(const std::string& path) {
    auto kind = asset::sniff_file(path);
    if (!kind.ok()) return kind.error();
    auto raw = asset::load_model_file(path);
    if (!raw.ok()) return raw.error();
    ModelSummary s;
    s.format = asset::file_kind_name(kind.value());
    s.up = asset::default_up_axis(kind.value()) == asset::UpAxis::z ? "z, turned to the scene's y (STL's convention: CAD and 3D printing; up = \"y\" in [model] reads it as y-up)"
                                                                    : "y (up = \"z\" in [model] for a z-up file)";
    s.vertices = raw->mesh.vertex_count();
    s.triangles = raw->mesh.triangle_count();
    if (raw->look) {
        const asset::SurfaceLook& look = *raw->look;
        s.materials = look.materials.size();
        for (const asset::Texture& t : look.textures)
            s.textures.push_back(t.name + " (" + std::to_string(t.width) + " x " + std::to_string(t.height) + ")");
        s.vertex_colors = !look.corner_color.empty();
        s.texture_coordinates = !look.uv.empty();
    }
    auto model = asset::load_model(path, {});
    if (!model.ok()) return model.error();
    s.repair = model->repaired.report.summary();
    s.refined_levels = model->refined_levels;
    s.warnings = std::move(raw->warnings);
    return s;
}

core::Result<Scene> load_scene_or_model(const std::string& path) {
    auto kind = input_kind(path);
    if (!kind.ok()) return kind.error();
    switch (kind.value()) {
    case InputKind::scene: return load_scene(path);
    case InputKind::model: return scene_for_model(path);
    case InputKind::gaussians: break;
    }
    return core::make_error(path, 0, "holds 3D Gaussians, not a scene or a model: only `pbdsplat render` and `pbdsplat info` take it");
}

} // namespace pbdsplat::scene
