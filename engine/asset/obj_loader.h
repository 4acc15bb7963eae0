#pragma once
// Wavefront OBJ input. The file is checked line by line first, so a broken file is refused
// with its file name, line and what is wrong; tinyobjloader then reads it (polygons as fans).
#include <string>

#include "core/result.h"
#include "asset/model_asset.h"
#include "mesh/triangle_mesh.h"

namespace pbdsplat::asset {

// Loads positions and triangles, plus normals, UVs and vertex colours when the file has them
// (per vertex: the first corner that names one wins). The result is raw: run repair() next.
// Polygons are split by ear clipping, so concave faces keep their shape.
core::Result<mesh::TriangleMesh> load_obj(const std::string& path);

// The same, from text in memory; `name` stands for the file in error messages.
core::Result<mesh::TriangleMesh> parse_obj(const std::string& text, const std::string& name);

// The mesh and its look: the .mtl files it names (Kd, map_Kd: textures found relative to the
// OBJ's folder, Windows separators accepted), per-corner texture coordinates, vertex colours.
core::Result<ModelAsset> load_obj_asset(const std::string& path);

} // namespace pbdsplat::asset
