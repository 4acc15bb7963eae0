#include "splat/ply.h"

#include <algorithm>
#include <cmath>
#include <bit>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

namespace pbdsplat::splat {
namespace {

constexpr float k_sh_c0 = 0.28209479177387814f;  // Y_0^0: colour = 0.5 + C0 * f_dc

uint32_t rest_count(uint32_t sh_degree) { return 3 * ((sh_degree + 1) * (sh_degree + 1) - 1); }

std::vector<std::string> property_names(uint32_t sh_degree) {
    std::vector<std::string> n = {"x", "y", "z", "nx", "ny", "nz", "f_dc_0", "f_dc_1", "f_dc_2"};
    for (uint32_t i = 0; i < rest_count(sh_degree); ++i) n.push_back("f_rest_" + std::to_string(i));
    for (const char* s : {"opacity", "scale_0", "scale_1", "scale_2", "rot_0", "rot_1", "rot_2", "rot_3"}) n.push_back(s);
    return n;
}

// The half turn about x that takes y-up to y-down and back: (x, y, z) -> (x, -y, -z).
const Eigen::Matrix3f k_half_turn_x = Vec3f(1.0f, -1.0f, -1.0f).asDiagonal();
// Under it, the spherical-harmonic basis functions of degree 1-3 (3DGS's order) that hold an
// odd number of y and z factors change sign.
constexpr bool k_sh_flips[15] = {true, true, false, true, false, false, true, false,
                                 true, false, true, true, false, true, false};

float logit(float p) { return std::log(p / (1.0f - p)); }

} // namespace

std::string ply_header(size_t count, uint32_t sh_degree) {
    std::string h = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(count) + "\n";
    for (const auto& name : property_names(sh_degree)) h += "property float " + name + "\n";
    return h + "end_header\n";
}

core::Status write_ply(const std::string& path, std::span<const GaussianRecord> records, std::span<const GaussianShape> shapes,
                       const PlyWriteOptions& options) {
    static_assert(std::endian::native == std::endian::little, "PLY writing assumes a little-endian host");
    if (!shapes.empty() && shapes.size() != records.size())
        return core::make_error(path, 0, "write_ply: " + std::to_string(shapes.size()) + " shapes for " + std::to_string(records.size()) + " records");
    if (options.sh_degree > 3) return core::make_error(path, 0, "write_ply: spherical-harmonic degree must be 0 to 3");
    std::ofstream out(path, std::ios::binary);
    if (!out) return core::make_error(path, 0, "cannot write (does the folder exist and is it writable?)");
    out << ply_header(records.size(), options.sh_degree);
    const size_t stride = property_names(options.sh_degree).size();
    const bool turn = options.up == PlyUp::minus_y;
    const Eigen::Matrix3f to_file = turn ? k_half_turn_x : Eigen::Matrix3f::Identity();
    std::vector<float> row(stride, 0.0f);
    for (size_t i = 0; i < records.size(); ++i) {
        const GaussianRecord& r = records[i];
        std::fill(row.begin(), row.end(), 0.0f);
        const Vec3f p = to_file * Vec3f(r.position[0], r.position[1], r.position[2]);
        row[0] = p.x(), row[1] = p.y(), row[2] = p.z();
        const Vec3f n = to_file * decode_octahedral(r.normal_oct);
        row[3] = n.x(), row[4] = n.y(), row[5] = n.z();
        for (int c = 0; c < 3; ++c) row[size_t(6 + c)] = (float(r.color[c]) / 255.0f - 0.5f) / k_sh_c0;
        const size_t o = 9 + rest_count(options.sh_degree);
        // The opacity a viewer sees: sigmoid(o) times the fade-in (a splat appearing after a
        // cut is as faint in the file as on screen).
        const float fade = float(r.color[3]) / 255.0f;
        const float alpha = fade / (1.0f + std::exp(-half_to_float(r.opacity_half)));
        row[o] = logit(std::clamp(alpha, 1e-6f, 1.0f - 1e-6f));
        if (shapes.empty()) {
            const float log_scale = std::log(std::max(half_to_float(r.scale_half), 1e-30f));
            row[o + 1] = row[o + 2] = row[o + 3] = log_scale;
            row[o + 4] = 1.0f;  // identity rotation, w first
        } else {
            // The covariance A A^T = V diag(lambda) V^T: V (made a proper rotation) and sqrt(lambda).
            const Eigen::Matrix3f a = to_file * shape_axes(shapes[i]);
            const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3f> eig(a * a.transpose());
            Eigen::Matrix3f v = eig.eigenvectors();
            if (v.determinant() < 0.0f) v.col(2) = -v.col(2);
            const Eigen::Quaternionf q(v);
            for (int k = 0; k < 3; ++k) row[o + 1 + size_t(k)] = std::log(std::max(std::sqrt(std::max(eig.eigenvalues()(k), 0.0f)), 1e-30f));
            row[o + 4] = q.w(), row[o + 5] = q.x(), row[o + 6] = q.y(), row[o + 7] = q.z();
        }
        out.write(reinterpret_cast<const char*>(row.data()), std::streamsize(row.size() * sizeof(float)));
    }
    if (!out) return core::make_error(path, 0, "write error (disk full?)");
    return core::Status::success();
}

core::Result<std::vector<GaussianRecord>> read_ply(const std::string& path, PlyUp up) {
    auto g = read_ply_gaussians(path, up);
    if (!g.ok()) return g.error();
    return std::move(g->records);
}

namespace {
struct PlyHeader {
    size_t count = 0, stride = 0;
    std::map<std::string, size_t> column;
    int last_line = 0;
};

// The header of a 3DGS .ply: one vertex element of float properties, binary little-endian.
core::Result<PlyHeader> read_header(std::ifstream& in, const std::string& path) {
    PlyHeader h;
    std::string line;
    int& line_no = h.last_line;
    auto next = [&]() -> bool {
        if (!std::getline(in, line)) return false;
        ++line_no;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        return true;
    };
    if (!next() || line != "ply") return core::make_error(path, 1, "not a PLY file (the first line must be 'ply')");
    bool have_vertex = false, in_vertex = false;
    while (true) {
        if (!next()) return core::make_error(path, line_no, "the header ends without 'end_header'");
        if (line == "end_header") break;
        std::istringstream ls(line);
        std::string word;
        ls >> word;
        if (word == "comment" || word == "obj_info") continue;
        if (word == "format") {
            std::string fmt, version;
            ls >> fmt >> version;
            if (fmt != "binary_little_endian")
                return core::make_error(path, line_no, "format '" + fmt + "' is not supported: 3DGS files are binary_little_endian");
        } else if (word == "element") {
            std::string name;
            long long n = -1;
            ls >> name >> n;
            if (have_vertex && in_vertex) return core::make_error(path, line_no, "elements after 'vertex' are not supported in a 3DGS file");
            in_vertex = name == "vertex";
            if (!in_vertex) return core::make_error(path, line_no, "element '" + name + "' is not part of a 3DGS file");
            if (n < 0) return core::make_error(path, line_no, "the vertex count must be a whole number >= 0");
            h.count = size_t(n);
            have_vertex = true;
        } else if (word == "property") {
            std::string type, name;
            ls >> type >> name;
            if (type.empty() || name.empty()) return core::make_error(path, line_no, "'property' needs a type and a name (is the header cut off?)");
            if (!in_vertex) return core::make_error(path, line_no, "property outside the vertex element");
            if (type != "float" && type != "float32")
                return core::make_error(path, line_no, "property '" + name + "' is " + type + "; 3DGS properties are float");
            h.column[name] = h.stride++;
        } else {
            return core::make_error(path, line_no, "unexpected header line '" + line + "'");
        }
    }
    if (!have_vertex) return core::make_error(path, line_no, "no 'element vertex' in the header");
    for (const char* need : {"x", "y", "z", "f_dc_0", "f_dc_1", "f_dc_2", "opacity", "scale_0", "scale_1", "scale_2"})
        if (!h.column.count(need)) return core::make_error(path, line_no, std::string("the header lacks property '") + need + "'");
    return h;
}

// The rows, after checking the announced count against the bytes present (before anything
// that size is allocated).
core::Result<std::vector<float>> read_rows(std::ifstream& in, const std::string& path, const PlyHeader& h) {
    const std::streamoff body_start = in.tellg();
    in.seekg(0, std::ios::end);
    const std::streamoff body_bytes = in.tellg() - body_start;
    in.seekg(body_start);
    const long double needed = (long double)h.count * (long double)h.stride * sizeof(float);
    if (needed > (long double)body_bytes)
        return core::make_error(path, 0, "truncated: the header announces " + std::to_string(h.count) + " Gaussians (" +
                                             std::to_string((unsigned long long)needed) + " bytes) but only " + std::to_string(body_bytes) +
                                             " bytes follow");
    std::vector<float> data(h.count * h.stride);
    in.read(reinterpret_cast<char*>(data.data()), std::streamsize(data.size() * sizeof(float)));
    if (size_t(in.gcount()) != data.size() * sizeof(float))
        return core::make_error(path, 0, "truncated: the header announces " + std::to_string(h.count) + " Gaussians (" +
                                             std::to_string(data.size() * sizeof(float)) + " bytes) but only " +
                                             std::to_string(in.gcount()) + " bytes follow");
    return data;
}

// Where each property sits in a row, looked up once, not per Gaussian: trained files hold
// millions. (Optional columns that are absent are never read.)
struct PlyColumns {
    size_t x, y, z, nx, ny, nz, dc[3], opacity, scale[3], rot[4];
    bool normals, rotations;
    uint32_t degree = 0, per_channel = 0;
    std::vector<size_t> rest;  // f_rest_*: per channel (d+1)^2 - 1, red's first, then green's, then blue's (3DGS's order)
};
PlyColumns find_columns(const std::map<std::string, size_t>& column) {
    auto at = [&](const char* name) { return column.count(name) ? column.at(name) : size_t(0); };
    PlyColumns c = {at("x"), at("y"), at("z"), at("nx"), at("ny"), at("nz"), {at("f_dc_0"), at("f_dc_1"), at("f_dc_2")}, at("opacity"),
                    {at("scale_0"), at("scale_1"), at("scale_2")}, {at("rot_0"), at("rot_1"), at("rot_2"), at("rot_3")},
                    column.count("nx") && column.count("ny") && column.count("nz"),
                    column.count("rot_0") && column.count("rot_1") && column.count("rot_2") && column.count("rot_3"), 0, 0, {}};
    uint32_t rest = 0;
    while (column.count("f_rest_" + std::to_string(rest))) ++rest;
    for (uint32_t d = 1; d <= 3; ++d)
        if (rest >= 3 * ((d + 1) * (d + 1) - 1)) c.degree = d;
    c.per_channel = (c.degree + 1) * (c.degree + 1) - 1;
    c.rest.resize(3 * c.per_channel);
    for (uint32_t j = 0; j < c.rest.size(); ++j) c.rest[j] = column.at("f_rest_" + std::to_string(j));
    return c;
}

// What one finite row decodes to, beside its record.
struct DecodedRow {
    Eigen::Matrix3f axes;
    bool missing_normal = false, round = true, any_rest = false;
};
core::Result<DecodedRow> decode_row(const float* row, const PlyColumns& cols, PlyUp up, const std::string& path, size_t i,
                                    GaussianRecord& r, GaussianSH* sh) {
    const Eigen::Matrix3f to_world = up == PlyUp::minus_y ? k_half_turn_x : Eigen::Matrix3f::Identity();
    DecodedRow d;
    const Vec3f p = to_world * Vec3f(row[cols.x], row[cols.y], row[cols.z]);
    r.position[0] = p.x(), r.position[1] = p.y(), r.position[2] = p.z();
    Vec3f n = cols.normals ? Vec3f(row[cols.nx], row[cols.ny], row[cols.nz]) : Vec3f::Zero();
    if (!(n.squaredNorm() > 1e-12f)) {
        d.missing_normal = true;  // estimated later, and counted, so the caller can say so
        n = Vec3f::UnitZ();
    }
    encode_octahedral(to_world * n.normalized(), r.normal_oct);
    for (int c = 0; c < 3; ++c) r.color[c] = uint8_t(std::lround(std::clamp(0.5f + k_sh_c0 * row[cols.dc[c]], 0.0f, 1.0f) * 255.0f));
    r.color[3] = 255;
    const Vec3f log_scale(row[cols.scale[0]], row[cols.scale[1]], row[cols.scale[2]]);
    const float s = log_scale.maxCoeff();
    r.scale_half = float_to_half(std::exp(s));
    r.opacity_half = float_to_half(row[cols.opacity]);
    d.round = s - log_scale.minCoeff() <= std::log(1.02f);  // round within 2 %: the rotation cannot show
    Eigen::Quaternionf q = Eigen::Quaternionf::Identity();
    if (cols.rotations) {
        q = Eigen::Quaternionf(row[cols.rot[0]], row[cols.rot[1]], row[cols.rot[2]], row[cols.rot[3]]);
        if (!(q.norm() > 1e-12f)) return core::make_error(path, 0, "Gaussian " + std::to_string(i) + " has a zero rotation quaternion");
        q.normalize();
    }
    d.axes = to_world * q.toRotationMatrix() * log_scale.array().exp().matrix().asDiagonal();
    if (sh) {
        std::fill(std::begin(sh->rest_half), std::end(sh->rest_half), uint16_t(0));
        for (uint32_t c = 0; c < 3; ++c)
            for (uint32_t k = 0; k < cols.per_channel; ++k) {
                float v = row[cols.rest[c * cols.per_channel + k]];
                d.any_rest = d.any_rest || v != 0.0f;
                // Seen from the turned world, a basis function odd in y and z flips sign.
                if (up == PlyUp::minus_y && k_sh_flips[k]) v = -v;
                sh->rest_half[15 * c + k] = float_to_half(v);
            }
    }
    return d;
}
} // namespace

core::Result<PlyGaussians> read_ply_gaussians(const std::string& path, PlyUp up, MissingNormals missing_normals) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) return core::make_error(path, 0, "is a folder, not a .ply file");
    std::ifstream in(path, std::ios::binary);
    if (!in) return core::make_error(path, 0, "cannot open the file (does it exist and is it readable?)");
    auto header = read_header(in, path);
    if (!header.ok()) return header.error();
    auto rows = read_rows(in, path, header.value());
    if (!rows.ok()) return rows.error();
    const std::vector<float>& data = rows.value();
    const size_t stride = header->stride, count = header->count;
    const PlyColumns cols = find_columns(header->column);

    PlyGaussians result;
    std::vector<GaussianRecord>& out = result.records;
    out.resize(count);
    if (cols.degree > 0) result.sh.resize(count);
    std::vector<Eigen::Matrix3f> axes(count);
    std::vector<uint8_t> missing(count, 0);
    bool round = true, any_rest = false;
    size_t kept = 0;
    for (size_t i = 0; i < count; ++i) {
        const float* row = data.data() + i * stride;
        // Trained files hold the odd NaN or infinite value: such a Gaussian is dropped, counted.
        if (!std::all_of(row, row + stride, [](float v) { return std::isfinite(v); })) {
            ++result.dropped_nonfinite;
            continue;
        }
        const size_t o = kept++;
        auto d = decode_row(row, cols, up, path, i, out[o], cols.degree > 0 ? &result.sh[o] : nullptr);
        if (!d.ok()) return d.error();
        axes[o] = d->axes;
        missing[o] = d->missing_normal;
        result.missing_normals += d->missing_normal;
        round = round && d->round;
        any_rest = any_rest || d->any_rest;
    }
    out.resize(kept);
    axes.resize(kept);
    missing.resize(kept);
    if (cols.degree > 0) result.sh.resize(kept);
    if (any_rest) result.sh_degree = cols.degree;
    else result.sh.clear();  // all zero (our own exports): nothing view-dependent
    if (!round) {
        result.shapes.resize(kept);
        for (size_t i = 0; i < kept; ++i) result.shapes[i] = make_shape(axes[i]);
    }
    if (result.missing_normals && missing_normals == MissingNormals::estimate) {
        result.estimated = estimate_normals(out, result.shapes, missing);
        result.normals_estimated = true;
    }
    return result;
}

} // namespace pbdsplat::splat
