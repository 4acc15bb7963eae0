#pragma once
// The scene that runs when none is given: an icosphere's vertices as Gaussians, lit by one
// directional light. Procedural, so it needs no model file.
#include <vector>

#include "mesh/triangle_mesh.h"
#include "render/frame_inputs.h"
#include "splat/gaussian_record.h"

namespace pbdsplat::scene {

struct BuiltinScene {
    mesh::TriangleMesh mesh;
    splat::Appearance appearance;
    render::FrameInputs frame;
    std::vector<splat::GaussianRecord> records;
};

// `level`: icosphere subdivision level (4 gives 2,562 Gaussians).
BuiltinScene make_builtin_scene(uint32_t level = 4);

} // namespace pbdsplat::scene
