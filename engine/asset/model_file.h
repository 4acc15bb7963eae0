#pragma once
// Any model file a user has, read by what its content is (asset/file_kind.h): OBJ with its
// materials, STL, PLY meshes, glTF 2.0. A file of another kind (a scene, Gaussians) is refused
// with what it is and what is accepted.
#include <string>

#include "asset/file_kind.h"
#include "asset/model_asset.h"
#include "core/result.h"

namespace pbdsplat::asset {

core::Result<ModelAsset> load_model_file(const std::string& path);

} // namespace pbdsplat::asset
