#include <doctest/doctest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include "splat/ply.h"

using namespace pbdsplat;

namespace {
std::string temp(const char* name) { return (std::filesystem::temp_directory_path() / name).string(); }

void write_text(const std::string& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }
} // namespace

TEST_SUITE("splat/ply") {
    TEST_CASE("the header is the standard 3DGS layout, byte for byte") {
        std::string expected =
            "ply\nformat binary_little_endian 1.0\nelement vertex 7\nproperty float x\nproperty float y\n"
            "property float z\nproperty float nx\nproperty float ny\nproperty float nz\nproperty float f_dc_0\n"
            "property float f_dc_1\nproperty float f_dc_2\n";
        for (int i = 0; i < 45; ++i) expected += "property float f_rest_" + std::to_string(i) + "\n";
        expected += "property float opacity\nproperty float scale_0\nproperty float scale_1\nproperty float scale_2\n"
                    "property float rot_0\nproperty float rot_1\nproperty float rot_2\nproperty float rot_3\nend_header\n";
        CHECK(splat::ply_header(7) == expected);
    }

    TEST_CASE("records survive a round trip within float precision") {
        std::mt19937 rng(11);
        std::uniform_real_distribution<float> u(-3.0f, 3.0f), c(0.0f, 1.0f), s(0.001f, 0.2f);
        std::vector<splat::GaussianRecord> records;
        for (int i = 0; i < 500; ++i) {
            splat::Appearance a;
            a.albedo = Vec3f(c(rng), c(rng), c(rng));
            a.opacity_logit = u(rng);
            a.scale = s(rng);
            records.push_back(splat::make_record(Vec3f(u(rng), u(rng), u(rng)), Vec3f(u(rng), u(rng), u(rng)).normalized(), a));
        }
        const std::string path = temp("pbdsplat_roundtrip.ply");
        REQUIRE(splat::write_ply(path, records).ok());
        CHECK(std::filesystem::file_size(path) == splat::ply_header(500).size() + 500 * 62 * sizeof(float));
        auto back = splat::read_ply(path);
        REQUIRE_MESSAGE(back.ok(), back.error().to_string());
        REQUIRE(back->size() == records.size());
        for (size_t i = 0; i < records.size(); ++i) {
            const auto& a = records[i];
            const auto& b = back.value()[i];
            for (int k = 0; k < 3; ++k) CHECK(a.position[k] == b.position[k]);
            for (int k = 0; k < 3; ++k) CHECK(a.color[k] == b.color[k]);
            CHECK(a.opacity_half == b.opacity_half);
            CHECK(std::abs(int(a.scale_half) - int(b.scale_half)) <= 1);  // exp(log(s)): within one half ulp
            CHECK(splat::decode_octahedral(a.normal_oct).dot(splat::decode_octahedral(b.normal_oct)) > 0.99999f);
        }
        std::filesystem::remove(path);
    }

    TEST_CASE("broken files are refused with the reason") {
        const std::string path = temp("pbdsplat_bad.ply");
        write_text(path, "ply\nformat ascii 1.0\nelement vertex 1\nend_header\n");
        CHECK(splat::read_ply(path).error().to_string() ==
              path + ":2: format 'ascii' is not supported: 3DGS files are binary_little_endian");
        write_text(path, "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\nend_header\n");
        CHECK(splat::read_ply(path).error().to_string() == path + ":5: the header lacks property 'y'");
        write_text(path, splat::ply_header(3) + std::string(100, '\0'));
        CHECK(splat::read_ply(path).error().message.find("truncated: the header announces 3 Gaussians") == 0);
        write_text(path, "PLY?\n");
        CHECK(splat::read_ply(path).error().to_string() == path + ":1: not a PLY file (the first line must be 'ply')");
        std::filesystem::remove(path);
    }
}
