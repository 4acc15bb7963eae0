#pragma once
// What a file is, told by its content (magic bytes, a PLY header's elements, the first
// statements of a text), not by its extension alone: a mesh saved as .txt or a scene without
// .toml still opens, and a Gaussian .ply is never read as a mesh (nor a mesh .ply as Gaussians).
#include <string>

#include "core/result.h"

namespace pbdsplat::asset {

enum class FileKind {
    scene,          // a TOML scene file
    obj,            // Wavefront OBJ (text)
    stl_ascii,
    stl_binary,
    ply_mesh,       // a PLY with a face element
    ply_gaussians,  // a PLY of 3D Gaussians (3DGS properties, no faces)
    gltf,           // glTF 2.0 JSON
    glb,            // glTF 2.0 binary container
};

const char* file_kind_name(FileKind kind);

// Reads the start of the file (and its size). Refuses, naming the file: one that cannot be
// read, an empty one, UTF-16 or UTF-32 text, a PLY point cloud (vertices without faces or
// Gaussian properties), and anything it does not recognise, with the list of what is accepted.
core::Result<FileKind> sniff_file(const std::string& path);
// The same on bytes in memory (`size` is the whole file's size; `head` may be its start only).
core::Result<FileKind> sniff_bytes(const std::string& head, uint64_t size, const std::string& name);

} // namespace pbdsplat::asset
