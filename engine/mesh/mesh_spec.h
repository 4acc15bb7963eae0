#pragma once
// A mesh named on a command line or in a scene: a procedural shape with its parameters, or an
// OBJ file (found along the model search path). Always returned repaired.
//   icosphere:LEVEL   uvsphere:RINGS:SEGMENTS   torus:SEGMENTS:SIDES   box:DIVISIONS
//   capsule:RINGS:SEGMENTS   grid:N   quadruped:DIVISIONS   path/to/file.obj or a model name like teapot.obj
#include <string>

#include "mesh/repair.h"

namespace pbdsplat::mesh {

struct MeshSpecOptions {
    // Files are centred and scaled to this bounding-box diagonal (0 keeps their own scale), so
    // scenes behave alike whatever units a model was saved in. Procedural shapes keep theirs.
    float file_fit_diagonal = 2.0f;
    bool close_holes = false;  // files: cap every boundary loop (RepairOptions::close_holes)
};

// True for the procedural kinds above (whatever their parameters), false for a file.
bool is_procedural_spec(const std::string& spec);

core::Result<RepairedMesh> load_mesh_spec(const std::string& spec, const MeshSpecOptions& options = {});

} // namespace pbdsplat::mesh
