#include "asset/file_kind.h"

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string_view>

namespace pbdsplat::asset {

using namespace std::string_view_literals;  // magic bytes with NULs in them

namespace {
// What pbdsplat opens, for refusals.
const char* const k_accepted_files =
    "accepted: a scene (.toml), a mesh as OBJ (with its .mtl), STL (ASCII or binary), PLY (ASCII or binary, with "
    "faces), glTF 2.0 (.gltf or .glb), or 3D Gaussians as a 3DGS .ply";
} // namespace

const char* file_kind_name(FileKind kind) {
    switch (kind) {
    case FileKind::scene: return "scene (TOML)";
    case FileKind::obj: return "OBJ mesh";
    case FileKind::stl_ascii: return "ASCII STL mesh";
    case FileKind::stl_binary: return "binary STL mesh";
    case FileKind::ply_mesh: return "PLY mesh";
    case FileKind::ply_gaussians: return "PLY of 3D Gaussians";
    case FileKind::gltf: return "glTF 2.0 (JSON)";
    case FileKind::glb: return "glTF 2.0 (binary .glb)";
    }
    return "?";
}

namespace {

bool starts_with(std::string_view s, std::string_view p) { return s.substr(0, p.size()) == p; }

std::string_view trim_left(std::string_view s) {
    size_t i = 0;
    while (i < s.size() && (s[i] == ' ' || s[i] == '\t' || s[i] == '\r' || s[i] == '\n')) ++i;
    return s.substr(i);
}

// The PLY header's verdict: faces make a mesh; 3DGS properties without faces make Gaussians.
core::Result<FileKind> sniff_ply(std::string_view head, const std::string& name) {
    const size_t end = head.find("end_header");
    if (end == std::string_view::npos)
        return core::make_error(name, 0, "a PLY file whose header has no 'end_header' (in its first " +
                                             std::to_string(head.size()) + " bytes): truncated or not PLY");
    std::istringstream in{std::string(head.substr(0, end))};
    std::string line;
    bool faces = false, gaussian = false, in_vertex = false;
    while (std::getline(in, line)) {
        std::istringstream words(line);
        std::string w, a, b, c;
        words >> w >> a >> b >> c;
        if (w == "element") {
            in_vertex = a == "vertex";
            if ((a == "face" || a == "triangle") && b != "0") faces = true;
        } else if (w == "property" && in_vertex) {
            const std::string& prop = a == "list" ? c : b;
            if (starts_with(prop, "f_dc_") || starts_with(prop, "scale_") || prop == "opacity" || starts_with(prop, "rot_"))
                gaussian = true;
        }
    }
    if (faces) return FileKind::ply_mesh;
    if (gaussian) return FileKind::ply_gaussians;
    return core::make_error(name, 0, "a PLY point cloud (vertices without faces or 3D Gaussian properties): pbdsplat "
                                     "simulates surfaces; mesh it first (e.g. Poisson reconstruction), or give a 3DGS .ply");
}

// OBJ or TOML by the first statement that is neither blank nor a comment (both use '#').
core::Result<FileKind> sniff_text(std::string_view head, const std::string& name) {
    size_t pos = 0;
    int line_no = 0;
    while (pos < head.size() && line_no < 200) {
        size_t nl = head.find('\n', pos);
        if (nl == std::string_view::npos) nl = head.size();
        std::string_view line = trim_left(head.substr(pos, nl - pos));
        pos = nl + 1;
        ++line_no;
        if (line.empty() || line[0] == '#') continue;
        if (line[0] == '[') return FileKind::scene;
        size_t w = 0;
        while (w < line.size() && line[w] != ' ' && line[w] != '\t' && line[w] != '=' && line[w] != '\r') ++w;
        const std::string_view word = line.substr(0, w);
        const std::string_view rest = trim_left(line.substr(w));
        if (!rest.empty() && rest[0] == '=') return FileKind::scene;
        for (const char* kw : {"v", "vn", "vt", "vp", "f", "o", "g", "s", "l", "p", "usemtl", "mtllib", "cstype", "deg", "curv"})
            if (word == kw) return FileKind::obj;
        if (word == "solid") return FileKind::stl_ascii;
        return core::make_error(name, line_no, "'" + std::string(word.substr(0, 40)) +
                                                   "' starts no statement of a format pbdsplat reads; " + k_accepted_files);
    }
    return core::make_error(name, 0, "holds nothing but blank lines and comments");
}

} // namespace

core::Result<FileKind> sniff_bytes(const std::string& head_bytes, uint64_t size, const std::string& name) {
    std::string_view head(head_bytes);
    if (size == 0) return core::make_error(name, 0, "the file is empty");
    if (starts_with(head, "\xFF\xFE\x00\x00"sv) || starts_with(head, "\x00\x00\xFE\xFF"sv))
        return core::make_error(name, 0, "is UTF-32 text; save it as UTF-8 (or ASCII) and try again");
    if (starts_with(head, "\xFF\xFE") || starts_with(head, "\xFE\xFF"))
        return core::make_error(name, 0, "is UTF-16 text; save it as UTF-8 (or ASCII) and try again");
    if (starts_with(head, "glTF")) return FileKind::glb;
    if (starts_with(head, "ply\n") || starts_with(head, "ply\r\n")) return sniff_ply(head, name);
    // Binary STL: an 80-byte header, a triangle count, 50 bytes a triangle. The size decides,
    // since many binary files begin their header with "solid" too.
    if (size >= 84 && head.size() >= 84) {
        uint32_t n = 0;
        std::memcpy(&n, head.data() + 80, 4);
        if (uint64_t(84) + uint64_t(n) * 50 == size) return FileKind::stl_binary;
    }
    if (starts_with(head, "PK\x03\x04"))
        return core::make_error(name, 0, "is a zip archive (3MF, USDZ, a zipped download?): unpack it; " + std::string(k_accepted_files));
    if (starts_with(head, "draco")) return core::make_error(name, 0, "is a Draco-compressed mesh, which pbdsplat does not decode; " + std::string(k_accepted_files));
    if (starts_with(head, "\xEF\xBB\xBF")) head.remove_prefix(3);  // a UTF-8 byte order mark
    const size_t probe = std::min<size_t>(head.size(), 4096);
    for (size_t i = 0; i < probe; ++i)
        if (head[i] == '\0')
            return core::make_error(name, 0, "is binary, but not a format pbdsplat reads (no glTF, PLY or binary STL "
                                             "signature); " + std::string(k_accepted_files));
    const std::string_view text = trim_left(head);
    if (starts_with(text, "{")) return FileKind::gltf;  // JSON: glTF is the only JSON format read
    if (starts_with(text, "solid") && head.find("facet") != std::string_view::npos) return FileKind::stl_ascii;
    return sniff_text(head, name);
}

core::Result<FileKind> sniff_file(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) return core::make_error(path, 0, "is a folder, not a file");
    std::ifstream f(path, std::ios::binary);
    if (!f) return core::make_error(path, 0, "cannot open the file (does it exist and is it readable?)");
    const uint64_t size = std::filesystem::file_size(path, ec);
    if (ec) return core::make_error(path, 0, "cannot read its size: " + ec.message());
    std::string head(size_t(std::min<uint64_t>(size, 64 * 1024)), '\0');
    f.read(head.data(), std::streamsize(head.size()));
    head.resize(size_t(f.gcount()));
    return sniff_bytes(head, size, path);
}

} // namespace pbdsplat::asset
