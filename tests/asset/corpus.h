#pragma once
// Small model files written by the tests themselves, one per format and encoding, into a fresh
// folder under the system's temporary directory.
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

namespace pbdsplat::test {

class Corpus {
public:
    explicit Corpus(const std::string& name)
        : dir_(std::filesystem::temp_directory_path() / ("pbdsplat-" + name + "-" + std::to_string(::getpid()))) {
        std::filesystem::remove_all(dir_);
        std::filesystem::create_directories(dir_);
    }
    ~Corpus() {
        std::error_code ec;
        std::filesystem::remove_all(dir_, ec);
    }
    std::string write(const std::string& name, const std::string& bytes) const {
        const std::filesystem::path p = dir_ / name;
        std::filesystem::create_directories(p.parent_path());
        std::ofstream(p, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
        return p.string();
    }
    std::string path(const std::string& name) const { return (dir_ / name).string(); }

private:
    std::filesystem::path dir_;
};

template <class T>
void put(std::string& s, T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    s.append(b, sizeof(T));
}

// The 12 triangles of the cube [0,1]^3, outward, as corner positions.
inline std::vector<float> cube_triangles() {
    const float v[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    const int f[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                          {2, 3, 7}, {2, 7, 6}, {1, 2, 6}, {1, 6, 5}, {0, 4, 7}, {0, 7, 3}};
    std::vector<float> out;
    for (const auto& t : f)
        for (int k : t) out.insert(out.end(), v[k], v[k] + 3);
    return out;
}

inline std::string binary_stl(const std::vector<float>& corners, const std::string& header = "binary cube") {
    std::string s(80, ' ');
    std::memcpy(s.data(), header.data(), std::min<size_t>(header.size(), 80));
    put<uint32_t>(s, uint32_t(corners.size() / 9));
    for (size_t t = 0; t < corners.size() / 9; ++t) {
        for (int k = 0; k < 3; ++k) put<float>(s, 0.0f);
        for (int k = 0; k < 9; ++k) put<float>(s, corners[t * 9 + size_t(k)]);
        put<uint16_t>(s, 0);
    }
    return s;
}

inline std::string ascii_stl(const std::vector<float>& corners) {
    std::string s = "solid cube\n";
    for (size_t t = 0; t < corners.size() / 9; ++t) {
        s += "  facet normal 0 0 0\n    outer loop\n";
        for (int k = 0; k < 3; ++k)
            s += "      vertex " + std::to_string(corners[t * 9 + size_t(k) * 3]) + " " + std::to_string(corners[t * 9 + size_t(k) * 3 + 1]) +
                 " " + std::to_string(corners[t * 9 + size_t(k) * 3 + 2]) + "\n";
        s += "    endloop\n  endfacet\n";
    }
    return s + "endsolid cube\n";
}

// An 8-vertex cube as OBJ, quads, with an optional material per face pair (top: "top").
inline std::string cube_obj(bool materials) {
    std::string s = materials ? "mtllib cube.mtl\n" : "";
    s += "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n";
    if (materials) s += "usemtl side\n";
    s += "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 1 5 8 4\n";
    if (materials) s += "usemtl top\n";
    s += "f 3 4 8 7\n";
    return s;
}

// A binary glTF (.glb) from its JSON and one binary buffer.
inline std::string glb(std::string json, std::string bin) {
    while (json.size() % 4) json += ' ';
    while (bin.size() % 4) bin += '\0';
    std::string s = "glTF";
    put<uint32_t>(s, 2);
    put<uint32_t>(s, uint32_t(12 + 8 + json.size() + (bin.empty() ? 0 : 8 + bin.size())));
    put<uint32_t>(s, uint32_t(json.size()));
    s += "JSON";
    s += json;
    if (!bin.empty()) {
        put<uint32_t>(s, uint32_t(bin.size()));
        s.append("BIN\0", 4);
        s += bin;
    }
    return s;
}

} // namespace pbdsplat::test
