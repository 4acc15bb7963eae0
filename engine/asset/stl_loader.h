#pragma once
// STL, ASCII and binary: a triangle soup (three vertices per facet, welded by repair()). The
// facet normals are ignored: repair orients the surface from its own winding.
#include <string>

#include "core/result.h"
#include "mesh/triangle_mesh.h"

namespace pbdsplat::asset {

// `bytes` is the whole file; `name` stands for it in messages.
core::Result<mesh::TriangleMesh> parse_stl_binary(const std::string& bytes, const std::string& name);
core::Result<mesh::TriangleMesh> parse_stl_ascii(const std::string& text, const std::string& name);

} // namespace pbdsplat::asset
