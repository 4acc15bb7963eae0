#include "asset/mesh_spec.h"

#include <algorithm>
#include <charconv>
#include <filesystem>
#include <mutex>
#include <optional>
#include <vector>

#include "asset/model_path.h"
#include "asset/model_file.h"
#include "mesh/procedural.h"
#include "mesh/subdivide.h"

namespace pbdsplat::asset {
namespace {

std::vector<std::string> split(const std::string& s, char sep) {
    std::vector<std::string> out;
    size_t start = 0;
    while (true) {
        const size_t end = s.find(sep, start);
        out.push_back(s.substr(start, end == std::string::npos ? std::string::npos : end - start));
        if (end == std::string::npos) return out;
        start = end + 1;
    }
}

core::Result<uint32_t> number(const std::string& spec, const std::string& field, uint32_t min, uint32_t max) {
    uint32_t v = 0;
    const auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), v);
    if (ec != std::errc() || end != field.data() + field.size() || v < min || v > max)
        return core::make_error("mesh '" + spec + "': '" + field + "' must be a whole number from " + std::to_string(min) +
                                " to " + std::to_string(max));
    return v;
}

// The last model file loaded, kept for the next load of the same file: a model named on the
// command line is read once for its scene (where it rests, how to frame it) and once more by
// the runtime, and reading and repairing a 100k-triangle file is a tenth of its first frame.
// Keyed by the file's path, size and time of change, and the options.
struct FileLoad {
    std::string path;
    std::filesystem::file_time_type written;
    uintmax_t size = 0;
    float fit = 0.0f;
    bool close_holes = false;
    UpAxis up = UpAxis::file_default;
    LoadedModel model;
};
std::mutex g_last_load_mutex;
std::optional<FileLoad> g_last_load;

bool same_file(const FileLoad& f, const std::string& path, const MeshSpecOptions& o) {
    std::error_code ec;
    return f.path == path && f.fit == o.file_fit_diagonal && f.close_holes == o.close_holes && f.up == o.up &&
           std::filesystem::last_write_time(path, ec) == f.written && std::filesystem::file_size(path, ec) == f.size && !ec;
}

std::optional<LoadedModel> last_file_load(const std::string& path, const MeshSpecOptions& o) {
    std::lock_guard lock(g_last_load_mutex);
    if (g_last_load && same_file(*g_last_load, path, o)) return g_last_load->model;
    return std::nullopt;
}

void remember_file_load(const std::string& path, const MeshSpecOptions& o, const LoadedModel& m) {
    std::error_code ec;
    FileLoad f{path, std::filesystem::last_write_time(path, ec), std::filesystem::file_size(path, ec), o.file_fit_diagonal, o.close_holes, o.up, m};
    if (ec) return;
    std::lock_guard lock(g_last_load_mutex);
    g_last_load = std::move(f);
}

// The procedural meshes a spec may name: kind, each parameter's range, the maker.
struct Procedural {
    const char* kind;
    std::vector<std::pair<uint32_t, uint32_t>> ranges;
    mesh::TriangleMesh (*make)(const std::vector<uint32_t>& a);
};
const std::vector<Procedural>& procedurals() {
    static const std::vector<Procedural> p = {
        {"icosphere", {{0, 8}}, [](const std::vector<uint32_t>& a) { return mesh::icosphere(a[0]); }},
        {"uvsphere", {{2, 2048}, {3, 4096}}, [](const std::vector<uint32_t>& a) { return mesh::uv_sphere(a[0], a[1]); }},
        {"torus", {{3, 4096}, {3, 4096}}, [](const std::vector<uint32_t>& a) { return mesh::torus(a[0], a[1]); }},
        {"box", {{1, 512}}, [](const std::vector<uint32_t>& a) { return mesh::box(Vec3f(1, 1, 1), a[0]); }},
        {"capsule", {{2, 2048}, {3, 4096}}, [](const std::vector<uint32_t>& a) { return mesh::capsule(0.5f, 1.0f, a[0], a[1]); }},
        {"grid", {{1, 2048}}, [](const std::vector<uint32_t>& a) { return mesh::grid_sheet(a[0], 2.0f); }},
        {"quadruped", {{1, 64}}, [](const std::vector<uint32_t>& a) { return mesh::quadruped(a[0]); }},
        {"table", {{1, 64}}, [](const std::vector<uint32_t>& a) { return mesh::table(a[0]); }},
    };
    return p;
}
const Procedural* find_procedural(const std::string& kind) {
    for (const Procedural& p : procedurals())
        if (kind == p.kind) return &p;
    return nullptr;
}

// `parts`: the spec split at ':'; each parameter read against its range.
core::Result<std::vector<uint32_t>> procedural_arguments(const Procedural& p, const std::string& spec, const std::vector<std::string>& parts) {
    if (parts.size() != p.ranges.size() + 1)
        return core::make_error("mesh '" + spec + "': " + p.kind + " takes " + std::to_string(p.ranges.size()) + " parameter(s)");
    std::vector<uint32_t> args;
    for (size_t i = 0; i < p.ranges.size(); ++i) {
        auto v = number(spec, parts[i + 1], p.ranges[i].first, p.ranges[i].second);
        if (!v.ok()) return v.error();
        args.push_back(v.value());
    }
    return args;
}

core::Result<LoadedModel> load_procedural(const Procedural& p, const std::string& spec, const std::vector<std::string>& parts) {
    auto args = procedural_arguments(p, spec, parts);
    if (!args.ok()) return args.error();
    mesh::RepairOptions o;
    o.weld_tolerance = 1e-6f;
    auto repaired = mesh::repair(p.make(args.value()), o, spec);
    if (!repaired.ok()) return repaired.error();
    return LoadedModel{std::move(repaired).value(), std::nullopt, {}, 0};
}

// z-up to y-up: a quarter turn about x, so +z becomes +y and +y (a z-up file's back) becomes -z.
void turn_z_up_to_y_up(ModelAsset& a) {
    const auto turn = [](std::vector<Vec3f>& v) {
        for (Vec3f& p : v) p = Vec3f(p.x(), p.z(), -p.y());
    };
    turn(a.mesh.positions);
    turn(a.mesh.normals);
    if (a.look) turn(a.look->positions);
}

UpAxis resolve_up(UpAxis asked, const std::string& path) {
    if (asked != UpAxis::file_default) return asked;
    const auto kind = sniff_file(path);
    return kind.ok() ? default_up_axis(kind.value()) : UpAxis::y;
}

// A model file: found on the search path, read, repaired and fitted, its look moved with it,
// refined when it has too few vertices to simulate; the last one kept for the next load.
core::Result<LoadedModel> load_file(const std::string& spec, const MeshSpecOptions& options) {
    const auto path = find_model(spec);
    std::error_code ec;
    if (!path && std::filesystem::is_directory(spec, ec))
        return core::make_error(spec + ": is a folder, not a mesh file (name a model file inside it, or a procedural mesh)");
    if (!path) {
        std::string where;
        for (const auto& d : model_search_path()) where += (where.empty() ? "" : ", ") + d;
        return core::make_error(spec + ": no such file, and not a procedural mesh (icosphere:L, uvsphere:R:S, "
                                       "torus:S:T, box:D, capsule:R:S, grid:N, quadruped:D, table:D); searched " + where);
    }
    if (auto cached = last_file_load(*path, options)) return std::move(*cached);
    auto raw = load_model_file(*path);
    if (!raw.ok()) return raw.error();
    if (resolve_up(options.up, *path) == UpAxis::z) turn_z_up_to_y_up(raw.value());
    mesh::RepairOptions o;
    o.center = options.file_fit_diagonal > 0.0f;
    o.fit_diagonal = options.file_fit_diagonal;
    o.close_holes = options.close_holes;
    LoadedModel out;
    out.look = std::move(raw.value().look);
    out.warnings = std::move(raw.value().warnings);
    auto repaired = mesh::repair(std::move(raw.value().mesh), o, *path);
    if (!repaired.ok()) return repaired.error();
    out.repaired = std::move(repaired).value();
    if (out.look)
        for (Vec3f& p : out.look->positions) p = (p + out.repaired.shift) * out.repaired.scale;
    out.refined_levels = mesh::refine_coarse_parts(out.repaired.mesh, k_part_edge_over_size, k_part_levels, k_refined_triangles);
    out.refined_levels = std::max(out.refined_levels, mesh::refine_to(out.repaired.mesh, k_min_file_vertices));
    remember_file_load(*path, options, out);
    return out;
}

} // namespace

UpAxis default_up_axis(FileKind kind) { return kind == FileKind::stl_ascii || kind == FileKind::stl_binary ? UpAxis::z : UpAxis::y; }

void forget_loads() {
    std::lock_guard lock(g_last_load_mutex);
    g_last_load.reset();
}

bool is_procedural_spec(const std::string& spec) { return find_procedural(split(spec, ':')[0]) != nullptr; }

core::Status check_procedural_spec(const std::string& spec) {
    const auto parts = split(spec, ':');
    const Procedural* p = find_procedural(parts[0]);
    if (!p) return core::make_error("mesh '" + spec + "' is not a procedural mesh");
    auto args = procedural_arguments(*p, spec, parts);
    if (!args.ok()) return args.error();
    return core::Status::success();
}

core::Result<LoadedModel> load_model(const std::string& spec, const MeshSpecOptions& options) {
    const auto parts = split(spec, ':');
    if (const Procedural* p = find_procedural(parts[0])) return load_procedural(*p, spec, parts);
    return load_file(spec, options);
}

core::Result<mesh::RepairedMesh> load_mesh_spec(const std::string& spec, const MeshSpecOptions& options) {
    auto m = load_model(spec, options);
    if (!m.ok()) return m.error();
    return std::move(m.value().repaired);
}

} // namespace pbdsplat::asset
