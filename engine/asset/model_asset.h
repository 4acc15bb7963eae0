#pragma once
// A model file as read: its raw surface (run mesh::repair next) and, when the file gives colour
// (materials, textures, vertex colours), its look on the same full-resolution triangles.
#include <optional>
#include <string>
#include <vector>

#include "asset/look.h"
#include "mesh/triangle_mesh.h"

namespace pbdsplat::asset {

struct ModelAsset {
    mesh::TriangleMesh mesh;
    std::optional<SurfaceLook> look;
    // What was read but not used, or used in part (a texture not found, a primitive that is not
    // triangles), for the user: the model still loads.
    std::vector<std::string> warnings;
};

// The look's geometry from the asset's mesh, with its per-triangle attributes left as given.
inline void share_geometry(ModelAsset& asset) {
    if (!asset.look) return;
    asset.look->positions = asset.mesh.positions;
    asset.look->triangles = asset.mesh.triangles;
}

} // namespace pbdsplat::asset
