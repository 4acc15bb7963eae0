#pragma once
// Wavefront OBJ input. The file is checked line by line first, so a broken file is refused
// with its file name, line and what is wrong; tinyobjloader then reads it (polygons as fans).
#include <string>

#include "core/result.h"
#include "mesh/triangle_mesh.h"

namespace pbdsplat::mesh {

// Loads positions and triangles, plus normals, UVs and vertex colours when the file has them
// (per vertex: the first corner that names one wins). The result is raw: run repair() next.
core::Result<TriangleMesh> load_obj(const std::string& path);

// The same, from text in memory; `name` stands for the file in error messages.
core::Result<TriangleMesh> parse_obj(const std::string& text, const std::string& name);

} // namespace pbdsplat::mesh
