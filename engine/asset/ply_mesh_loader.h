#pragma once
// PLY meshes (ASCII, binary little- and big-endian): vertex positions, colours (red/green/blue
// as bytes or floats), texture coordinates (s/t, u/v, texture_u/texture_v) and faces (any list
// of vertex indices, polygons split by ear clipping); other elements and properties skipped. A
// MeshLab "comment TextureFile" names the texture the coordinates refer to.
#include <string>

#include "asset/model_asset.h"
#include "core/result.h"

namespace pbdsplat::asset {

// `bytes` is the whole file; `base_dir` is where a named texture is looked for.
core::Result<ModelAsset> parse_ply_mesh(const std::string& bytes, const std::string& name, const std::string& base_dir);

} // namespace pbdsplat::asset
