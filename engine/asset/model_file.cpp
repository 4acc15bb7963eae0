#include "asset/model_file.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "asset/gltf_loader.h"
#include "asset/obj_loader.h"
#include "asset/ply_mesh_loader.h"
#include "asset/stl_loader.h"

namespace pbdsplat::asset {
namespace {

core::Result<std::string> read_bytes(const std::string& path) {
    std::ifstream file(path, std::ios::binary);
    if (!file) return core::make_error(path, 0, "cannot open the file (does it exist and is it readable?)");
    std::ostringstream s;
    s << file.rdbuf();
    if (file.bad()) return core::make_error(path, 0, "read error");
    return s.str();
}

core::Result<ModelAsset> mesh_only(core::Result<mesh::TriangleMesh> m) {
    if (!m.ok()) return m.error();
    ModelAsset a;
    a.mesh = std::move(m).value();
    return a;
}

} // namespace

core::Result<ModelAsset> load_model_file(const std::string& path) {
    auto kind = sniff_file(path);
    if (!kind.ok()) return kind.error();
    const std::string dir = std::filesystem::path(path).parent_path().string();
    switch (kind.value()) {
    case FileKind::obj: return load_obj_asset(path);
    case FileKind::gltf: return load_gltf(path, false);
    case FileKind::glb: return load_gltf(path, true);
    case FileKind::stl_ascii:
    case FileKind::stl_binary:
    case FileKind::ply_mesh: {
        auto bytes = read_bytes(path);
        if (!bytes.ok()) return bytes.error();
        if (kind.value() == FileKind::ply_mesh) return parse_ply_mesh(bytes.value(), path, dir);
        return mesh_only(kind.value() == FileKind::stl_binary ? parse_stl_binary(bytes.value(), path) : parse_stl_ascii(bytes.value(), path));
    }
    case FileKind::scene:
        return core::make_error(path, 0, "is a scene file, not a model: name it as the scene, and a model in its [model] mesh");
    case FileKind::ply_gaussians:
        return core::make_error(path, 0, "holds 3D Gaussians, not a mesh: render it directly (pbdsplat render FILE.ply); a scene's model must be a surface");
    }
    return core::make_error(path, 0, "unrecognised file");
}

} // namespace pbdsplat::asset
