#include "asset/ply_mesh_loader.h"

#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <span>
#include <sstream>

#include "core/image.h"
#include "mesh/polygon.h"

namespace pbdsplat::asset {
namespace {

enum class Type : uint8_t { i8, u8, i16, u16, i32, u32, f32, f64, none };

Type type_of(const std::string& s) {
    if (s == "char" || s == "int8") return Type::i8;
    if (s == "uchar" || s == "uint8") return Type::u8;
    if (s == "short" || s == "int16") return Type::i16;
    if (s == "ushort" || s == "uint16") return Type::u16;
    if (s == "int" || s == "int32") return Type::i32;
    if (s == "uint" || s == "uint32") return Type::u32;
    if (s == "float" || s == "float32") return Type::f32;
    if (s == "double" || s == "float64") return Type::f64;
    return Type::none;
}

size_t size_of(Type t) {
    switch (t) {
    case Type::i8: case Type::u8: return 1;
    case Type::i16: case Type::u16: return 2;
    case Type::i32: case Type::u32: case Type::f32: return 4;
    case Type::f64: return 8;
    default: return 0;
    }
}

struct Property {
    std::string name;
    Type type = Type::none;
    Type count_type = Type::none;  // a list's length type; none for a scalar
};

struct Element {
    std::string name;
    uint64_t count = 0;
    std::vector<Property> properties;
};

enum class Format { ascii, little, big };

struct Header {
    Format format = Format::ascii;
    std::vector<Element> elements;
    std::string texture_file;
    size_t data_start = 0;
};

// The rest of a 'property' line: a type and a name, or 'list', its count and item types and a name.
core::Result<Property> read_property(std::istringstream& w) {
    Property p;
    std::string t;
    w >> t;
    if (t == "list") {
        std::string ct, it;
        w >> ct >> it >> p.name;
        p.count_type = type_of(ct);
        p.type = type_of(it);
        if (p.count_type == Type::none || p.type == Type::none || p.count_type == Type::f32 || p.count_type == Type::f64)
            return core::make_error("list property '" + p.name + "' has an unknown or non-integer type");
    } else {
        p.type = type_of(t);
        w >> p.name;
        if (p.type == Type::none) return core::make_error("property '" + p.name + "' has unknown type '" + t + "'");
    }
    return p;
}

core::Result<Header> read_header(const std::string& bytes, const std::string& name) {
    Header h;
    const size_t end = bytes.find("end_header");
    if (end == std::string::npos) return core::make_error(name, 0, "PLY header without 'end_header'");
    size_t nl = bytes.find('\n', end);
    h.data_start = nl == std::string::npos ? bytes.size() : nl + 1;
    std::istringstream in(bytes.substr(0, end));
    std::string line;
    int line_no = 0;
    bool format_seen = false;
    while (std::getline(in, line)) {
        ++line_no;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        std::istringstream w(line);
        std::string kw;
        w >> kw;
        auto err = [&](const std::string& what) { return core::make_error(name, line_no, what); };
        if (kw == "format") {
            std::string f, version;
            w >> f >> version;
            if (f == "ascii") h.format = Format::ascii;
            else if (f == "binary_little_endian") h.format = Format::little;
            else if (f == "binary_big_endian") h.format = Format::big;
            else return err("PLY format '" + f + "' is not ascii, binary_little_endian or binary_big_endian");
            format_seen = true;
        } else if (kw == "element") {
            Element e;
            std::string count;
            w >> e.name >> count;
            const auto [p, ec] = std::from_chars(count.data(), count.data() + count.size(), e.count);
            if (ec != std::errc() || p != count.data() + count.size()) return err("element '" + e.name + "' has no valid count");
            h.elements.push_back(std::move(e));
        } else if (kw == "property") {
            if (h.elements.empty()) return err("a property before any element");
            auto p = read_property(w);
            if (!p.ok()) return err(p.error().message);
            h.elements.back().properties.push_back(std::move(p.value()));
        } else if (kw == "comment" || kw == "obj_info") {
            std::string what, file;
            w >> what;
            if (what == "TextureFile") std::getline(w >> std::ws, h.texture_file);
        } else if (kw != "ply" && !kw.empty()) {
            return err("'" + kw + "' is not a PLY header statement");
        }
    }
    if (!format_seen) return core::make_error(name, 0, "PLY header has no 'format' line");
    return h;
}

// Reads values one at a time from the body, ASCII or binary, with a position for messages.
class Reader {
public:
    Reader(const std::string& bytes, size_t start, Format f, const std::string& name) : b_(bytes), pos_(start), f_(f), name_(name) {}
    core::Result<double> next(Type t) {
        if (f_ == Format::ascii) {
            while (pos_ < b_.size() && std::isspace(static_cast<unsigned char>(b_[pos_]))) ++pos_;
            size_t e = pos_;
            while (e < b_.size() && !std::isspace(static_cast<unsigned char>(b_[e]))) ++e;
            if (e == pos_) return truncated();
            double v = 0.0;
            const auto [p, ec] = std::from_chars(b_.data() + pos_, b_.data() + e, v);
            if (ec != std::errc() || p != b_.data() + e)
                return core::make_error(name_, 0, "PLY body: '" + b_.substr(pos_, std::min<size_t>(e - pos_, 40)) + "' is not a number");
            pos_ = e;
            return v;
        }
        const size_t n = size_of(t);
        if (pos_ + n > b_.size()) return truncated();
        unsigned char raw[8];
        std::memcpy(raw, b_.data() + pos_, n);
        pos_ += n;
        if ((f_ == Format::big) != (std::endian::native == std::endian::big))
            for (size_t i = 0; i < n / 2; ++i) std::swap(raw[i], raw[n - 1 - i]);
        switch (t) {
        case Type::i8: return double(int8_t(raw[0]));
        case Type::u8: return double(raw[0]);
        case Type::i16: { int16_t v; std::memcpy(&v, raw, 2); return double(v); }
        case Type::u16: { uint16_t v; std::memcpy(&v, raw, 2); return double(v); }
        case Type::i32: { int32_t v; std::memcpy(&v, raw, 4); return double(v); }
        case Type::u32: { uint32_t v; std::memcpy(&v, raw, 4); return double(v); }
        case Type::f32: { float v; std::memcpy(&v, raw, 4); return double(v); }
        case Type::f64: { double v; std::memcpy(&v, raw, 8); return v; }
        default: return 0.0;
        }
    }

private:
    core::Error truncated() const { return core::make_error(name_, 0, "PLY body ends before the header's elements do: truncated?"); }
    const std::string& b_;
    size_t pos_;
    Format f_;
    const std::string& name_;
};

int find_prop(const Element& e, std::initializer_list<const char*> names) {
    for (const char* n : names)
        for (size_t i = 0; i < e.properties.size(); ++i)
            if (e.properties[i].name == n) return int(i);
    return -1;
}

float colour_value(double v, Type t) {
    const double scale = t == Type::u8 ? 255.0 : t == Type::u16 ? 65535.0 : 1.0;
    return float(std::clamp(v / scale, 0.0, 1.0));
}

// Where an element's properties are (-1: absent), under the names exporters use.
struct Columns {
    int x = -1, y = -1, z = -1, r = -1, g = -1, b = -1, u = -1, v = -1, face = -1;
};
Columns columns_of(const Element& e) {
    Columns c;
    c.x = find_prop(e, {"x"}), c.y = find_prop(e, {"y"}), c.z = find_prop(e, {"z"});
    c.r = find_prop(e, {"red", "r", "diffuse_red"}), c.g = find_prop(e, {"green", "g", "diffuse_green"});
    c.b = find_prop(e, {"blue", "b", "diffuse_blue"});
    c.u = find_prop(e, {"s", "u", "texture_u", "texture_s"}), c.v = find_prop(e, {"t", "v", "texture_v", "texture_t"});
    c.face = find_prop(e, {"vertex_indices", "vertex_index"});
    return c;
}

// One row of an element: its scalars into `row`, and the list at `keep` (-1: none) into `list`
// (a negative index kept as UINT32_MAX, refused later as out of range).
core::Status read_row(Reader& r, const Element& e, int keep, std::vector<double>& row, std::vector<uint32_t>& list, const std::string& name) {
    for (size_t p = 0; p < e.properties.size(); ++p) {
        const Property& prop = e.properties[p];
        if (prop.count_type == Type::none) {
            auto v = r.next(prop.type);
            if (!v.ok()) return v.error();
            row[p] = v.value();
            continue;
        }
        auto len = r.next(prop.count_type);
        if (!len.ok()) return len.error();
        if (!(len.value() >= 0.0) || len.value() > 1e6) return core::make_error(name, 0, "PLY list of length " + std::to_string(len.value()));
        const bool kept = int(p) == keep;
        if (kept) list.clear();
        for (uint32_t j = 0; j < uint32_t(len.value()); ++j) {
            auto v = r.next(prop.type);
            if (!v.ok()) return v.error();
            if (kept) list.push_back(v.value() < 0.0 ? UINT32_MAX : uint32_t(v.value()));
        }
    }
    return core::Status::success();
}

// A polygon of the face list, split in its own plane; points and lines are not surface.
core::Status add_face(std::span<const uint32_t> polygon, uint64_t k, mesh::TriangleMesh& m, std::vector<Vec3f>& corners,
                      const std::string& name) {
    if (polygon.size() < 3) return core::Status::success();
    corners.clear();
    for (uint32_t v : polygon) {
        if (v >= m.positions.size())
            return core::make_error(name, 0, "PLY face " + std::to_string(k) + " refers to vertex " + std::to_string(v) + " of " +
                                                 std::to_string(m.positions.size()));
        corners.push_back(m.positions[v]);
    }
    for (const auto& t : mesh::triangulate_polygon(corners)) m.triangles.push_back({polygon[t[0]], polygon[t[1]], polygon[t[2]]});
    return core::Status::success();
}

// The vertices and faces of every element, in file order; `uvs` gets each vertex's texture
// coordinate where the file has them.
core::Status read_elements(const Header& h, Reader& r, mesh::TriangleMesh& m, std::vector<Vec2f>& uvs, const std::string& name) {
    for (const Element& e : h.elements) {
        const bool vertex = e.name == "vertex", face = e.name == "face";
        const Columns c = columns_of(e);
        if (vertex && (c.x < 0 || c.y < 0 || c.z < 0)) return core::make_error(name, 0, "PLY vertices without x, y and z");
        if (face && (c.face < 0 || e.properties[size_t(c.face)].count_type == Type::none))
            return core::make_error(name, 0, "PLY faces without a 'vertex_indices' list");
        const bool colour = vertex && c.r >= 0 && c.g >= 0 && c.b >= 0;
        if (e.count > (uint64_t(1) << 31)) return core::make_error(name, 0, "PLY element '" + e.name + "' counts " + std::to_string(e.count) + ": too many");
        std::vector<double> row(e.properties.size());
        std::vector<uint32_t> polygon;
        std::vector<Vec3f> corners;
        for (uint64_t k = 0; k < e.count; ++k) {
            PBDSPLAT_TRY(read_row(r, e, face ? c.face : -1, row, polygon, name));
            if (face) PBDSPLAT_TRY(add_face(polygon, k, m, corners, name));
            if (!vertex) continue;
            const Vec3f x{float(row[size_t(c.x)]), float(row[size_t(c.y)]), float(row[size_t(c.z)])};
            if (!x.allFinite()) return core::make_error(name, 0, "PLY vertex " + std::to_string(k) + " has a non-finite coordinate");
            m.positions.push_back(x);
            if (colour)
                m.colors.emplace_back(colour_value(row[size_t(c.r)], e.properties[size_t(c.r)].type),
                                      colour_value(row[size_t(c.g)], e.properties[size_t(c.g)].type),
                                      colour_value(row[size_t(c.b)], e.properties[size_t(c.b)].type));
            if (c.u >= 0 && c.v >= 0) uvs.emplace_back(float(row[size_t(c.u)]), 1.0f - float(row[size_t(c.v)]));
        }
    }
    return core::Status::success();
}

// A MeshLab `comment TextureFile` with per-vertex coordinates: the image over every triangle.
void attach_texture(const Header& h, const std::string& base_dir, const std::string& name, std::span<const Vec2f> uvs,
                    const mesh::TriangleMesh& m, SurfaceLook& look, std::vector<std::string>& warnings) {
    if (h.texture_file.empty() || uvs.size() != m.positions.size()) return;
    std::filesystem::path p = std::filesystem::path(base_dir.empty() ? "." : base_dir) / h.texture_file;
    auto image = core::read_image(p.string());
    if (!image.ok()) {
        warnings.push_back(name + ": texture '" + h.texture_file + "' not read (" + image.error().to_string() + ")");
        return;
    }
    look.textures.push_back(Texture{p.string(), image->width, image->height, std::move(image->pixels)});
    look.materials.push_back(Material{"texture", Vec3f::Ones(), 0});
    look.material.assign(m.triangles.size(), 0);
    look.uv.resize(m.triangles.size());
    for (size_t t = 0; t < m.triangles.size(); ++t)
        for (size_t k = 0; k < 3; ++k) look.uv[t][k] = uvs[m.triangles[t][k]];
}

} // namespace

core::Result<ModelAsset> parse_ply_mesh(const std::string& bytes, const std::string& name, const std::string& base_dir) {
    auto header = read_header(bytes, name);
    if (!header.ok()) return header.error();
    const Header& h = header.value();
    Reader r(bytes, h.data_start, h.format, name);
    ModelAsset out;
    mesh::TriangleMesh& m = out.mesh;
    std::vector<Vec2f> uvs;
    PBDSPLAT_TRY(read_elements(h, r, m, uvs, name));
    if (m.triangles.empty()) return core::make_error(name, 0, "PLY with no faces of three or more vertices: nothing to simulate");
    // Colours only where every vertex has one.
    if (m.colors.size() != m.positions.size()) m.colors.clear();
    SurfaceLook look;
    if (!m.colors.empty()) {
        look.corner_color.resize(m.triangles.size());
        for (size_t t = 0; t < m.triangles.size(); ++t)
            for (size_t k = 0; k < 3; ++k) look.corner_color[t][k] = srgb_to_linear(m.colors[m.triangles[t][k]]);
    }
    attach_texture(h, base_dir, name, uvs, m, look, out.warnings);
    if (look.has_colour()) {
        out.look = std::move(look);
        share_geometry(out);
    }
    return out;
}

} // namespace pbdsplat::asset
