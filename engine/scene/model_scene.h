#pragma once
// A model file named where a scene is expected (`pbdsplat run model.glb`): the scene a user
// would write for it. The model fitted to a 2-unit diagonal (about a metre a side) and resting on
// a drawn ground, the camera framing it and orbiting slowly, the default material, simulation
// size and environment, normalised blending. `pbdsplat ... --save-scene FILE.toml` writes it out
// to edit.
#include <string>

#include "core/result.h"
#include "scene/scene.h"

namespace pbdsplat::scene {

// What a command-line path names, by its content (asset/file_kind.h).
enum class InputKind { scene, model, gaussians };
core::Result<InputKind> input_kind(const std::string& path);

// The scene's text (TOML, as a user would edit it), and the scene read from it. `mesh_as` is
// how the text names the model (a path relative to where the text is saved); empty: as given.
core::Result<std::string> model_scene_text(const std::string& model_path, const std::string& mesh_as = "");
core::Result<Scene> scene_for_model(const std::string& model_path);

// What pbdsplat reads from a model file, for `pbdsplat info FILE`: so that a user sees which
// materials, textures and colours were found before running it.
struct ModelSummary {
    std::string format;
    std::string up;  // the axis read as up, and why
    size_t vertices = 0, triangles = 0;  // as read (before welding)
    size_t materials = 0;
    std::vector<std::string> textures;  // "file (W x H)"
    bool vertex_colors = false, texture_coordinates = false;
    std::string repair;                 // mesh::RepairReport::summary() of the repaired surface
    uint32_t refined_levels = 0;
    std::vector<std::string> warnings;
};
core::Result<ModelSummary> summarize_model(const std::string& path);

// A scene file, or a model file's scene; Gaussians are refused (they are rendered as they are).
core::Result<Scene> load_scene_or_model(const std::string& path);

} // namespace pbdsplat::scene
