#include "asset/obj_loader.h"

#include <cctype>
#include <charconv>
#include <filesystem>
#include <cmath>
#include <fstream>
#include <optional>
#include <span>
#include <sstream>
#include <string_view>
#include <vector>

#include <tiny_obj_loader.h>

#include "core/image.h"
#include "mesh/polygon.h"

namespace pbdsplat::asset {
namespace {

std::vector<std::string_view> split_ws(std::string_view line) {
    std::vector<std::string_view> out;
    size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
        const size_t start = i;
        while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
        if (i > start) out.push_back(line.substr(start, i - start));
    }
    return out;
}

bool parse_float(std::string_view s, float& out) {
    // from_chars for float is in libstdc++ 11+, and rejects what strtof would half-accept.
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
    return ec == std::errc() && end == s.data() + s.size();
}

bool parse_int(std::string_view s, long& out) {
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
    return ec == std::errc() && end == s.data() + s.size();
}

// What the line-by-line check learns about the file.
struct ObjFacts {
    size_t positions = 0, normals = 0, uvs = 0, faces = 0;
    bool colors = false;
};

// A v/vn/vt line's numbers (after the keyword): between `min` and `max` of them, each a finite
// number. `what` names the statement in the message.
std::optional<std::string> check_numbers(std::span<const std::string_view> tok, size_t min, size_t max, const char* what) {
    const size_t n = tok.size() - 1;
    if (n < min || n > max) {
        std::string range = std::to_string(min);
        if (min != max) range.append(" to ").append(std::to_string(max));
        return std::string(what) + " needs " + range + " numbers, found " + std::to_string(n);
    }
    for (size_t i = 1; i < tok.size(); ++i) {
        float v = 0.0f;
        if (!parse_float(tok[i], v)) return "'" + std::string(tok[i]) + "' is not a number";
        if (!std::isfinite(v)) return std::string(what) + " has a non-finite value '" + std::string(tok[i]) + "'";
    }
    return std::nullopt;
}

// An 'f' line's corners (v, v/vt, v//vn or v/vt/vn), each index referring to an element
// defined above it (negative: counted back from the last).
std::optional<std::string> check_face(std::span<const std::string_view> tok, const ObjFacts& f) {
    if (tok.size() < 4) return "face 'f' needs at least 3 vertices, found " + std::to_string(tok.size() - 1);
    // tinyobjloader counts a face's corners in a byte.
    if (tok.size() - 1 > 255) return "face 'f' has " + std::to_string(tok.size() - 1) + " corners; at most 255 are read (split the polygon)";
    for (size_t i = 1; i < tok.size(); ++i) {
        const std::string_view corner = tok[i];
        size_t part = 0, start = 0;
        for (size_t k = 0; k <= corner.size(); ++k) {
            if (k < corner.size() && corner[k] != '/') continue;
            const std::string_view field = corner.substr(start, k - start);
            start = k + 1;
            const size_t count = part == 0 ? f.positions : part == 1 ? f.uvs : f.normals;
            const char* what = part == 0 ? "vertex" : part == 1 ? "texture coordinate" : "normal";
            ++part;
            if (field.empty()) {
                if (part == 1) return "face corner '" + std::string(corner) + "' has no vertex index";
                continue;
            }
            if (part > 3) return "face corner '" + std::string(corner) + "' has more than three indices";
            long idx = 0;
            if (!parse_int(field, idx)) return "face index '" + std::string(field) + "' is not an integer";
            if (idx == 0) return std::string("face index 0 is invalid (OBJ indices start at 1)");
            const long resolved = idx > 0 ? idx : long(count) + idx + 1;
            if (resolved < 1 || resolved > long(count))
                return "face refers to " + std::string(what) + " " + std::to_string(idx) + ", but only " + std::to_string(count) +
                       " are defined above this line";
        }
    }
    return std::nullopt;
}

// Checks every v/vn/vt/f line: numbers that parse and are finite, enough of them, face indices
// that refer to elements defined before the face (OBJ allows nothing else).
core::Result<ObjFacts> check_obj(const std::string& text, const std::string& name) {
    ObjFacts f;
    size_t colored = 0;
    std::istringstream in(text);
    std::string raw;
    int line_no = 0;
    auto err = [&](const std::string& what) { return core::make_error(name, line_no, what); };
    while (std::getline(in, raw)) {
        ++line_no;
        const std::string_view line(raw);
        const size_t hash = line.find('#');
        const auto tok = split_ws(hash == std::string_view::npos ? line : line.substr(0, hash));
        if (tok.empty()) continue;
        const std::string_view kw = tok[0];
        std::optional<std::string> wrong;
        if (kw == "v") {
            wrong = check_numbers(tok, 3, 7, "vertex 'v'");
            if (tok.size() == 7 || tok.size() == 8) ++colored;
            ++f.positions;
        } else if (kw == "vn") {
            wrong = check_numbers(tok, 3, 3, "normal 'vn'");
            ++f.normals;
        } else if (kw == "vt") {
            wrong = check_numbers(tok, 1, 3, "texture coordinate 'vt'");
            ++f.uvs;
        } else if (kw == "f") {
            wrong = check_face(tok, f);
            ++f.faces;
        }
        // Other statements (o, g, s, usemtl, mtllib, l, p, ...) do not affect the surface.
        if (wrong) return err(*wrong);
    }
    line_no = 0;
    if (f.positions == 0) return err("no vertices ('v' lines)");
    if (f.faces == 0) return err("no faces ('f' lines): nothing to simulate or render");
    if (colored != 0 && colored != f.positions)
        return err("vertex colours on " + std::to_string(colored) + " of " + std::to_string(f.positions) +
                   " vertices: give every 'v' line a colour, or none");
    f.colors = colored == f.positions;
    return f;
}

std::string lower(std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

// A map_Kd path as written: relative to the .mtl's folder, with Windows separators, or an
// absolute path from the author's machine (C:\Users\...\Textures\skin.jpg). Tried in turn: as
// written, its last folder and name beside the model (Textures/skin.jpg), its name beside the
// model, then its name ignoring case beside the model or one folder down (exporters and
// archive tools change case and folder names).
std::string find_texture(const std::string& base_dir, std::string name) {
    for (char& c : name)
        if (c == '\\') c = '/';
    const std::filesystem::path dir(base_dir.empty() ? "." : base_dir), given(name);
    std::vector<std::filesystem::path> tries{given.is_absolute() ? given : dir / given};
    if (given.has_parent_path()) tries.push_back(dir / given.parent_path().filename() / given.filename());
    tries.push_back(dir / given.filename());
    std::error_code ec;
    for (const std::filesystem::path& p : tries)
        if (std::filesystem::is_regular_file(p, ec)) return p.lexically_normal().string();
    const std::string want = lower(given.filename().string());
    // Iterated with error codes throughout: an unreadable folder is skipped, never thrown from.
    auto entries = [](const std::filesystem::path& folder) {
        std::vector<std::filesystem::directory_entry> out;
        std::error_code e;
        for (std::filesystem::directory_iterator it(folder, e), end; !e && it != end; it.increment(e)) out.push_back(*it);
        return out;
    };
    std::vector<std::filesystem::path> folders{dir};
    for (const auto& e : entries(dir))
        if (e.is_directory(ec)) folders.push_back(e.path());
    for (const std::filesystem::path& folder : folders)
        for (const auto& e : entries(folder))
            if (e.is_regular_file(ec) && lower(e.path().filename().string()) == want) return e.path().lexically_normal().string();
    return {};
}

// Materials and textures as SurfaceLook takes them; a texture that cannot be read leaves its
// material's colour, with a warning.
void read_materials(const std::vector<tinyobj::material_t>& in, const std::string& base_dir, const std::string& name,
                    SurfaceLook& look, std::vector<std::string>& warnings) {
    for (const tinyobj::material_t& m : in) {
        Material out;
        out.name = m.name;
        out.color = Vec3f(m.diffuse[0], m.diffuse[1], m.diffuse[2]).cwiseMax(0.0f).cwiseMin(1.0f);
        if (!m.diffuse_texname.empty()) {
            const std::string path = find_texture(base_dir, m.diffuse_texname);
            auto image = path.empty() ? core::Result<core::ImageRgba8>(core::make_error(m.diffuse_texname + ": not found"))
                                      : core::read_image(path);
            if (!image.ok()) {
                warnings.push_back(name + ": material '" + m.name + "': texture '" + m.diffuse_texname +
                                   "' not read (" + image.error().to_string() + "); its colour Kd is used");
            } else {
                Texture t;
                t.name = path;
                t.width = image->width;
                t.height = image->height;
                t.rgba = std::move(image->pixels);
                // A texture multiplies Kd; exporters often leave Kd at 0.8 or 0 beside a map.
                out.color = Vec3f::Ones();
                out.texture = int32_t(look.textures.size());
                look.textures.push_back(std::move(t));
            }
        }
        look.materials.push_back(std::move(out));
    }
}

// The loader passes some indices through unchecked (found by fuzzing: a face's
// texture-coordinate index past the vt lines read past the array).
core::Status check_corners(const tinyobj::attrib_t& a, std::span<const tinyobj::index_t> face, size_t n, const std::string& name) {
    for (const tinyobj::index_t& c : face) {
        if (c.vertex_index < 0 || size_t(c.vertex_index) >= n)
            return core::make_error(name, 0, "a face refers to vertex " + std::to_string(c.vertex_index + 1) + " of " + std::to_string(n));
        if (c.normal_index >= 0 && size_t(c.normal_index) * 3 + 2 >= a.normals.size())
            return core::make_error(name, 0, "a face refers to normal " + std::to_string(c.normal_index + 1) + " of " +
                                                 std::to_string(a.normals.size() / 3));
        if (c.texcoord_index >= 0 && size_t(c.texcoord_index) * 2 + 1 >= a.texcoords.size())
            return core::make_error(name, 0, "a face refers to texture coordinate " + std::to_string(c.texcoord_index + 1) + " of " +
                                                 std::to_string(a.texcoords.size() / 2));
    }
    return core::Status::success();
}

// The file's faces as triangles of the mesh, with what each corner carries (the first normal
// and texture coordinate a vertex is given, per-corner texture coordinates and the face's
// material for the look).
class FaceBuilder {
public:
    FaceBuilder(const tinyobj::attrib_t& a, mesh::TriangleMesh& m, SurfaceLook& look, bool want_look)
        : a_(a), m_(m), look_(look), has_normals_(!a.normals.empty()), has_uvs_(!a.texcoords.empty()),
          textured_(want_look && has_uvs_ && !look.textures.empty()), per_material_(want_look && !look.materials.empty()),
          normal_set_(m.positions.size(), false), uv_set_(m.positions.size(), false) {
        if (has_normals_) m.normals.assign(m.positions.size(), Vec3f::Zero());
        if (has_uvs_) m.uvs.assign(m.positions.size(), Vec2f::Zero());
    }

    // A checked face (check_corners) of `material` (-1: none), split in its own plane.
    void add(std::span<const tinyobj::index_t> face, int material) {
        corners_.clear();
        for (const tinyobj::index_t& c : face) corners_.push_back(m_.positions[size_t(c.vertex_index)]);
        for (const auto& tri : mesh::triangulate_polygon(corners_)) {
            mesh::Triangle t{};
            std::array<Vec2f, 3> uv{};
            for (size_t k = 0; k < 3; ++k) t[k] = take_corner(face[tri[k]], uv[k]);
            m_.triangles.push_back(t);
            if (textured_) look_.uv.push_back(uv);
            if (per_material_) {
                const bool named = material >= 0 && size_t(material) < look_.materials.size();
                look_.material.push_back(named ? uint32_t(material) : uint32_t(look_.materials.size()));
                unnamed_ = unnamed_ || !named;
            }
        }
    }
    // Faces before any usemtl, or naming a material no .mtl defines, get a plain white one.
    void finish() {
        if (unnamed_) look_.materials.push_back(Material{"(none)", Vec3f::Ones(), -1});
    }

private:
    uint32_t take_corner(const tinyobj::index_t& c, Vec2f& uv) {
        const auto v = uint32_t(c.vertex_index);
        if (has_normals_ && c.normal_index >= 0 && !normal_set_[v]) {
            const size_t q = size_t(c.normal_index) * 3;
            m_.normals[v] = Vec3f(a_.normals[q], a_.normals[q + 1], a_.normals[q + 2]);
            normal_set_[v] = true;
        }
        if (has_uvs_ && c.texcoord_index >= 0) {
            const size_t q = size_t(c.texcoord_index) * 2;
            const Vec2f tc(a_.texcoords[q], a_.texcoords[q + 1]);
            if (!uv_set_[v]) m_.uvs[v] = tc, uv_set_[v] = true;
            uv = Vec2f(tc.x(), 1.0f - tc.y());  // OBJ's v runs up, the images' rows down
        }
        return v;
    }

    const tinyobj::attrib_t& a_;
    mesh::TriangleMesh& m_;
    SurfaceLook& look_;
    const bool has_normals_, has_uvs_, textured_, per_material_;
    std::vector<bool> normal_set_, uv_set_;
    std::vector<Vec3f> corners_;
    bool unnamed_ = false;
};

// Positions, and vertex colours where every vertex has them.
void copy_vertices(const tinyobj::attrib_t& a, bool colors, mesh::TriangleMesh& m) {
    const size_t n = a.vertices.size() / 3;
    m.positions.resize(n);
    for (size_t i = 0; i < n; ++i) m.positions[i] = Vec3f(a.vertices[3 * i], a.vertices[3 * i + 1], a.vertices[3 * i + 2]);
    if (!colors || a.colors.size() != a.vertices.size()) return;
    m.colors.resize(n);
    for (size_t i = 0; i < n; ++i) m.colors[i] = Vec3f(a.colors[3 * i], a.colors[3 * i + 1], a.colors[3 * i + 2]);
}

core::Result<ModelAsset> read_obj(const std::string& text, const std::string& name, const std::string& base_dir, bool want_look) {
    auto facts = check_obj(text, name);
    if (!facts.ok()) return facts.error();

    tinyobj::attrib_t a;
    std::vector<tinyobj::shape_t> shapes;
    std::vector<tinyobj::material_t> materials;
    std::string warn, error;
    std::istringstream stream(text);
    std::string dir = base_dir.empty() ? std::string(".") : base_dir;
    if (dir.back() != '/') dir += '/';
    tinyobj::MaterialFileReader mtl_reader(dir);
    // Polygons are split here (mesh/polygon.h), not by the loader: its fan and ear rules fill
    // concave outlines.
    if (!tinyobj::LoadObj(&a, &shapes, &materials, &warn, &error, &stream, want_look ? &mtl_reader : nullptr, false, false))
        return core::make_error(name, 0, "tinyobjloader refused the file: " + error);

    ModelAsset out;
    mesh::TriangleMesh& m = out.mesh;
    copy_vertices(a, facts->colors, m);
    SurfaceLook look;
    if (want_look) {
        if (warn.find("material") != std::string::npos || warn.find(".mtl") != std::string::npos)
            out.warnings.push_back(name + ": " + warn.substr(0, warn.find('\n')));
        read_materials(materials, base_dir, name, look, out.warnings);
    }
    FaceBuilder faces(a, m, look, want_look);
    for (const tinyobj::shape_t& shape : shapes) {
        size_t offset = 0;
        for (size_t f = 0; f < shape.mesh.num_face_vertices.size(); ++f) {
            const std::span<const tinyobj::index_t> face(shape.mesh.indices.data() + offset, shape.mesh.num_face_vertices[f]);
            PBDSPLAT_TRY(check_corners(a, face, m.positions.size(), name));
            faces.add(face, f < shape.mesh.material_ids.size() ? shape.mesh.material_ids[f] : -1);
            offset += face.size();
        }
    }
    faces.finish();
    if (want_look && !m.colors.empty()) {
        look.corner_color.resize(m.triangles.size());
        for (size_t t = 0; t < m.triangles.size(); ++t)
            for (size_t k = 0; k < 3; ++k) look.corner_color[t][k] = srgb_to_linear(m.colors[m.triangles[t][k]]);
    }
    if (want_look && look.has_colour()) {
        out.look = std::move(look);
        share_geometry(out);
    }
    return out;
}

} // namespace

core::Result<mesh::TriangleMesh> parse_obj(const std::string& text, const std::string& name) {
    auto r = read_obj(text, name, "", false);
    if (!r.ok()) return r.error();
    return std::move(r.value().mesh);
}

namespace {
core::Result<std::string> read_text(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) return core::make_error(path, 0, "is a folder, not an .obj file");
    std::ifstream file(path, std::ios::binary);
    if (!file) return core::make_error(path, 0, "cannot open the file (does it exist and is it readable?)");
    std::ostringstream text;
    text << file.rdbuf();
    if (file.bad()) return core::make_error(path, 0, "read error");
    std::string s = text.str();
    if (s.compare(0, 3, "\xEF\xBB\xBF") == 0) s.erase(0, 3);  // a UTF-8 byte order mark
    return s;
}
} // namespace

core::Result<mesh::TriangleMesh> load_obj(const std::string& path) {
    auto text = read_text(path);
    if (!text.ok()) return text.error();
    return parse_obj(text.value(), path);
}

core::Result<ModelAsset> load_obj_asset(const std::string& path) {
    auto text = read_text(path);
    if (!text.ok()) return text.error();
    return read_obj(text.value(), path, std::filesystem::path(path).parent_path().string(), true);
}

} // namespace pbdsplat::asset
