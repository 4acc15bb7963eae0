#include "asset/stl_loader.h"

#include <charconv>
#include <cmath>
#include <cstring>
#include <sstream>

namespace pbdsplat::asset {

core::Result<mesh::TriangleMesh> parse_stl_binary(const std::string& bytes, const std::string& name) {
    if (bytes.size() < 84) return core::make_error(name, 0, "a binary STL needs 84 bytes of header, the file has " + std::to_string(bytes.size()));
    uint32_t n = 0;
    std::memcpy(&n, bytes.data() + 80, 4);
    if (uint64_t(84) + uint64_t(n) * 50 != bytes.size())
        return core::make_error(name, 0, "binary STL: the header counts " + std::to_string(n) + " triangles (" +
                                             std::to_string(84 + uint64_t(n) * 50) + " bytes) but the file has " +
                                             std::to_string(bytes.size()) + " bytes: truncated?");
    if (n == 0) return core::make_error(name, 0, "binary STL with no triangles");
    mesh::TriangleMesh m;
    m.positions.reserve(size_t(n) * 3);
    m.triangles.reserve(n);
    for (uint32_t t = 0; t < n; ++t) {
        const char* rec = bytes.data() + 84 + size_t(t) * 50 + 12;  // past the facet normal
        float v[9];
        std::memcpy(v, rec, sizeof v);
        for (float x : v)
            if (!std::isfinite(x)) return core::make_error(name, 0, "binary STL: triangle " + std::to_string(t + 1) + " has a non-finite coordinate");
        const uint32_t base = uint32_t(m.positions.size());
        for (int k = 0; k < 3; ++k) m.positions.emplace_back(v[3 * k], v[3 * k + 1], v[3 * k + 2]);
        m.triangles.push_back({base, base + 1, base + 2});
    }
    return m;
}

core::Result<mesh::TriangleMesh> parse_stl_ascii(const std::string& text, const std::string& name) {
    mesh::TriangleMesh m;
    std::istringstream in(text);
    std::string line;
    int line_no = 0, in_loop = 0, facet_line = 0;
    auto err = [&](const std::string& what) { return core::make_error(name, line_no, what); };
    while (std::getline(in, line)) {
        ++line_no;
        std::istringstream words(line);
        std::string kw;
        if (!(words >> kw)) continue;
        if (kw == "vertex") {
            if (in_loop == 0) return err("'vertex' outside an 'outer loop'");
            if (in_loop > 3) return err("a facet with more than three vertices");
            float v[3];
            for (float& x : v) {
                std::string w;
                if (!(words >> w)) return err("'vertex' needs three numbers");
                const auto [end, ec] = std::from_chars(w.data(), w.data() + w.size(), x);
                if (ec != std::errc() || end != w.data() + w.size()) return err("'" + w + "' is not a number");
                if (!std::isfinite(x)) return err("a non-finite coordinate '" + w + "'");
            }
            m.positions.emplace_back(v[0], v[1], v[2]);
            ++in_loop;
        } else if (kw == "outer") {
            in_loop = 1;
            facet_line = line_no;
        } else if (kw == "endloop") {
            if (in_loop != 4) return err("a facet needs exactly three vertices, this one has " + std::to_string(std::max(in_loop - 1, 0)));
            const uint32_t base = uint32_t(m.positions.size() - 3);
            m.triangles.push_back({base, base + 1, base + 2});
            in_loop = 0;
        } else if (kw != "solid" && kw != "endsolid" && kw != "facet" && kw != "endfacet") {
            return err("'" + kw.substr(0, 40) + "' is not an ASCII STL statement (solid, facet, outer loop, vertex, endloop, endfacet, endsolid)");
        }
    }
    if (in_loop != 0) {
        line_no = facet_line;
        return err("the file ends inside this facet's loop: truncated?");
    }
    if (m.triangles.empty()) return core::make_error(name, 0, "ASCII STL with no facets");
    return m;
}

} // namespace pbdsplat::asset
