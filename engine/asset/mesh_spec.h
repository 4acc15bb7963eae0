#pragma once
// A mesh named on a command line or in a scene: a procedural shape with its parameters, or an
// model file of any kind asset/model_file.h reads (found along the model search path). Always
// returned repaired.
//   icosphere:LEVEL   uvsphere:RINGS:SEGMENTS   torus:SEGMENTS:SIDES   box:DIVISIONS
//   capsule:RINGS:SEGMENTS   grid:N   quadruped:DIVISIONS   table:DIVISIONS   path/to/file.obj or a model name like teapot.obj
#include <optional>
#include <string>
#include <vector>

#include "asset/file_kind.h"
#include "asset/look.h"
#include "core/names.h"
#include "mesh/repair.h"

namespace pbdsplat::asset {

// Which way is up in a model file. The scene is y-up, as glTF's convention and most OBJ exports
// are; STL files come from CAD and 3D printing, which are z-up (a print stands on z = 0), so a
// figurine read as y-up lay on its back.
enum class UpAxis { file_default, y, z };
inline constexpr core::EnumName<UpAxis> k_up_axis_names[] = {{UpAxis::file_default, "auto"}, {UpAxis::y, "y"}, {UpAxis::z, "z"}};
// The axis a file of `kind` is read with when nothing says: z for STL, y for the rest.
UpAxis default_up_axis(FileKind kind);

struct MeshSpecOptions {
    // Files are centred and scaled to this bounding-box diagonal (0 keeps their own scale), so
    // scenes behave alike whatever units a model was saved in. Procedural shapes keep theirs.
    float file_fit_diagonal = 2.0f;
    bool close_holes = false;  // files: cap every boundary loop (RepairOptions::close_holes)
    UpAxis up = UpAxis::file_default;  // files: turned so that this axis is the scene's +y
};

// A model file of fewer vertices than this is subdivided (flat) until it has them: the sampling
// spacing follows the edge length, and an 8-vertex cube would be drawn as eight huge splats.
inline constexpr size_t k_min_file_vertices = 200;
// And a part of a file whose longest edge passes 0.35 of its own size (its bounding diagonal) is
// subdivided (flat) until none does (at most 4 times; the file kept within 100,000 triangles):
// an 8-vertex box among finer parts takes 2 levels, as a box alone does above; suzanne's
// low-poly eyes (0.30) and every part of the shared models are left as they are
// (mesh::refine_coarse_parts).
inline constexpr float k_part_edge_over_size = 0.35f;
inline constexpr uint32_t k_part_levels = 4;
inline constexpr size_t k_refined_triangles = 100000;
// A procedural mesh's parameter is its resolution, chosen by the user, and kept; below this many
// vertices (a box of one to three divisions, an icosahedron) every splat would span a face, so a
// scene subdivides it flat until it has them (asset users that ask for the mesh itself get it).
inline constexpr size_t k_min_procedural_vertices = 64;

// True for the procedural kinds above (whatever their parameters), false for a file.
bool is_procedural_spec(const std::string& spec);
// Whether a procedural spec's parameters are in range, without making the mesh: what a scene
// file's reader asks, so that the refusal names the file and line.
core::Status check_procedural_spec(const std::string& spec);

struct LoadedModel {
    mesh::RepairedMesh repaired;
    // A file's look (textures, materials, vertex colours), moved with the repair's centring and
    // scaling so it lies on the repaired surface; empty when the file gives no colour.
    std::optional<SurfaceLook> look;
    std::vector<std::string> warnings;
    uint32_t refined_levels = 0;  // flat subdivisions of a tiny file
};

core::Result<LoadedModel> load_model(const std::string& spec, const MeshSpecOptions& options = {});
// Forgets the last file loaded (kept so that a model's scene and its runtime read it once),
// so that the next load reads the file again: for benchmarks of a first load.
void forget_loads();

// The surface alone.
core::Result<mesh::RepairedMesh> load_mesh_spec(const std::string& spec, const MeshSpecOptions& options = {});

} // namespace pbdsplat::asset
