#pragma once
// glTF 2.0, JSON (.gltf with its buffers and images beside it, or embedded as data URIs) and
// binary (.glb), read with tinygltf: the default scene's mesh nodes with their transforms
// (matrix or translation/rotation/scale, down the node tree), triangle primitives (lists, strips,
// fans), baseColorFactor, baseColorTexture with its sampler's wrap modes and TEXCOORD_0, and
// COLOR_0. Refused with the reason: Draco or meshopt compression, a file with no triangles.
#include <string>

#include "asset/model_asset.h"
#include "core/result.h"

namespace pbdsplat::asset {

core::Result<ModelAsset> load_gltf(const std::string& path, bool binary);

} // namespace pbdsplat::asset
