#include <doctest/doctest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>

#include <Eigen/Geometry>

#include "splat/ply.h"
#include "support/why.h"

using namespace pbdsplat;

namespace {
std::string temp(const char* name) { return (std::filesystem::temp_directory_path() / name).string(); }

void write_text(const std::string& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }
} // namespace

// Little-endian float32 bytes, as a PLY body holds them.
std::string floats(std::initializer_list<float> values) {
    std::string out;
    for (float v : values) out.append(reinterpret_cast<const char*>(&v), sizeof(float));
    return out;
}

Eigen::Matrix3f covariance(const Eigen::Matrix3f& axes) { return axes * axes.transpose(); }

// The header of `count` Gaussians without normals: position, colour, opacity, scales, rotation.
std::string header_without_normals(int count) {
    std::string header = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(count) + "\n";
    for (const char* name : {"x", "y", "z", "f_dc_0", "f_dc_1", "f_dc_2", "opacity", "scale_0", "scale_1", "scale_2", "rot_0", "rot_1",
                             "rot_2", "rot_3"})
        header += std::string("property float ") + name + "\n";
    return header + "end_header\n";
}

TEST_SUITE("splat/ply") {
    TEST_CASE("normals a file lacks are estimated for lighting, or left (+z, counted) when nothing lights them") {
        // One flat Gaussian, thinnest along x: its estimate is its flattest axis.
        const std::string header = header_without_normals(1);
        const std::string path = temp("pbdsplat_flat_no_normal.ply");
        write_text(path, header + floats({0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 2.0f, std::log(0.01f), std::log(0.3f), std::log(0.3f),
                                          1.0f, 0.0f, 0.0f, 0.0f}));
        auto estimated = splat::read_ply_gaussians(path, splat::PlyUp::y);
        REQUIRE_MESSAGE(estimated.ok(), test::why(estimated));
        CHECK(estimated->missing_normals == 1);
        CHECK(estimated->normals_estimated);
        CHECK(estimated->estimated.from_shape == 1);
        CHECK(std::abs(splat::decode_octahedral(estimated->records[0].normal_oct).x()) > 0.999f);  // the flat Gaussians shortest axis, to 16-bit octahedral rounding
        auto left = splat::read_ply_gaussians(path, splat::PlyUp::y, splat::MissingNormals::leave);
        REQUIRE_MESSAGE(left.ok(), test::why(left));
        CHECK(left->missing_normals == 1);
        CHECK_FALSE(left->normals_estimated);
        CHECK(left->estimated.from_shape == 0);
        CHECK(splat::decode_octahedral(left->records[0].normal_oct).z() > 0.9999f);  // the default +z, to octahedral rounding
        std::filesystem::remove(path);
    }

    TEST_CASE("a file written by hand, properties shuffled and no normals, reads as the 3DGS convention says") {
        // Written here byte by byte, not by our writer: colour = 0.5 + Y_0^0 f_dc with
        // Y_0^0 = 1 / (2 sqrt(pi)), scales are natural logs, rot_0..3 = w x y z, opacity a logit.
        const char* order[] = {"opacity", "rot_1", "x", "scale_2", "f_dc_0", "y", "rot_0", "scale_0", "z",
                               "f_dc_2",  "rot_3", "scale_1", "f_dc_1", "rot_2"};
        std::string header = "ply\nformat binary_little_endian 1.0\nelement vertex 2\n";
        for (const char* name : order) header += std::string("property float ") + name + "\n";
        header += "end_header\n";
        const float c = std::cos(math::radians(22.5f)), sn = std::sin(math::radians(22.5f));  // 45 degrees about z
        const float l1 = std::log(0.1f), a = std::log(0.3f), b = std::log(0.05f), d = std::log(0.02f);
        // Gaussian 0: round, at (1, 2, 3). Gaussian 1: a needle along (1, 1, 0) / sqrt(2).
        const std::string body = floats({2.0f, 0.0f, 1.0f, l1, 0.0f, 2.0f, 1.0f, l1, 3.0f, 0.0f, 0.0f, l1, 0.0f, 0.0f}) +
                                 floats({-1.0f, 0.0f, 0.0f, d, 1.0f, 0.0f, c, a, 0.0f, -1.0f, sn, b, 0.0f, 0.0f});
        const std::string path = temp("pbdsplat_by_hand.ply");
        write_text(path, header + body);
        auto g = splat::read_ply_gaussians(path, splat::PlyUp::y);  // the file's own frame
        REQUIRE_MESSAGE(g.ok(), test::why(g));
        REQUIRE(g->records.size() == 2);
        CHECK(g->missing_normals == 2);
        REQUIRE(g->shapes.size() == 2);  // one needle makes the whole file anisotropic
        const auto& r0 = g->records[0];
        CHECK(r0.position[0] == 1.0f);
        CHECK(r0.position[1] == 2.0f);
        CHECK(r0.position[2] == 3.0f);
        CHECK(splat::half_to_float(r0.opacity_half) == doctest::Approx(2.0f).epsilon(1e-3));
        CHECK(splat::half_to_float(r0.scale_half) == doctest::Approx(0.1f).epsilon(1e-3));
        CHECK(splat::decode_octahedral(r0.normal_oct).z() > 0.9999f);  // no normals: +z
        const float y00 = 0.5f / std::sqrt(k_pi);
        const auto& r1 = g->records[1];
        CHECK(int(r1.color[0]) == int(std::lround((0.5f + y00) * 255.0f)));
        CHECK(int(r1.color[1]) == 128);
        CHECK(int(r1.color[2]) == int(std::lround((0.5f - y00) * 255.0f)));
        CHECK(splat::half_to_float(r1.scale_half) == doctest::Approx(0.3f).epsilon(1e-3));  // the longest axis
        const Eigen::Matrix3f rot = Eigen::AngleAxisf(math::radians(45.0f), Vec3f::UnitZ()).toRotationMatrix();
        const Eigen::Matrix3f expected = covariance(rot * Vec3f(0.3f, 0.05f, 0.02f).asDiagonal());
        CHECK((covariance(splat::shape_axes(g->shapes[1])) - expected).norm() < 2e-3f * expected.norm());
        CHECK((covariance(splat::shape_axes(g->shapes[0])) - 0.01f * Eigen::Matrix3f::Identity()).norm() < 1e-4f);
        // Read as 3DGS's y-down file (the default): a half turn about x into our y-up world.
        auto turned = splat::read_ply_gaussians(path);
        REQUIRE(turned.ok());
        CHECK(turned->records[0].position[0] == 1.0f);
        CHECK(turned->records[0].position[1] == -2.0f);
        CHECK(turned->records[0].position[2] == -3.0f);
        const Eigen::Matrix3f half_turn = Vec3f(1.0f, -1.0f, -1.0f).asDiagonal();
        const Eigen::Matrix3f turned_expected = half_turn * expected * half_turn;
        CHECK((covariance(splat::shape_axes(turned->shapes[1])) - turned_expected).norm() < 2e-3f * expected.norm());
        CHECK(splat::decode_octahedral(turned->records[0].normal_oct).z() < -0.9999f);  // file +z is our -z
        std::filesystem::remove(path);
    }

    TEST_CASE("a file's NaN or infinite Gaussians are dropped and counted; a huge count is refused before allocating") {
        std::string header = "ply\nformat binary_little_endian 1.0\nelement vertex 3\n";
        for (const char* name : {"x", "y", "z", "f_dc_0", "f_dc_1", "f_dc_2", "opacity", "scale_0", "scale_1", "scale_2"})
            header += std::string("property float ") + name + "\n";
        header += "end_header\n";
        const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
        const std::string body = floats({0, 0, 0, 0, 0, 0, 2, -2, -2, -2}) + floats({1, 0, 0, 0, 0, 0, inf, -2, -2, -2}) +
                                 floats({2, 0, 0, 0, 0, 0, 2, nan, -2, -2});
        const std::string path = temp("pbdsplat_nonfinite.ply");
        write_text(path, header + body);
        auto g = splat::read_ply_gaussians(path);
        REQUIRE_MESSAGE(g.ok(), test::why(g));
        CHECK(g->records.size() == 1);
        CHECK(g->dropped_nonfinite == 2);
        // Four billion Gaussians announced, forty bytes present: an error naming both, no allocation.
        std::string huge = header;
        huge.replace(huge.find("vertex 3"), 8, "vertex 4000000000");
        write_text(path, huge + floats({0, 0, 0, 0, 0, 0, 2, -2, -2, -2}));
        auto refused = splat::read_ply(path);
        REQUIRE_FALSE(refused.ok());
        CHECK(refused.error().message.find("announces 4000000000 Gaussians") != std::string::npos);
        // A header cut off inside a property line says so.
        write_text(path, "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty");
        auto cut = splat::read_ply(path);
        REQUIRE_FALSE(cut.ok());
        CHECK(cut.error().to_string() == path + ":4: 'property' needs a type and a name (is the header cut off?)");
        // A folder is not a file.
        CHECK(splat::read_ply(std::filesystem::temp_directory_path().string()).error().message == "is a folder, not a .ply file");
        std::filesystem::remove(path);
    }

    TEST_CASE("a file written by splat-transform (another tool's layout, no normals, .spz's quantisation) reads as made") {
        // tests/splat/fixtures/README.md: these three Gaussians, written by hand in the 3DGS
        // convention, then through splat-transform to .spz and back to .ply.
        struct Made {
            Vec3f p;
            Vec3f dc;
            float opacity;
            Vec3f scales;
            Eigen::Quaternionf q;
        };
        const Made made[] = {
            {{0.5f, -1.0f, 2.0f}, {1.0f, 0.0f, -1.0f}, 2.0f, {0.1f, 0.1f, 0.1f}, Eigen::Quaternionf::Identity()},
            {{-1.0f, 0.25f, 0.0f}, {0.5f, 0.5f, 0.5f}, -1.0f, {0.3f, 0.05f, 0.02f},
             Eigen::Quaternionf(Eigen::AngleAxisf(k_pi / 4.0f, Vec3f::UnitZ()))},
            {{2.0f, 2.0f, -2.0f}, {-0.5f, 1.5f, 0.0f}, 0.0f, {0.2f, 0.2f, 0.2f}, Eigen::Quaternionf::Identity()}};
        auto g = splat::read_ply_gaussians(std::string(PBDSPLAT_PLY_FIXTURES_DIR) + "/splat_transform_from_spz.ply", splat::PlyUp::y);
        REQUIRE_MESSAGE(g.ok(), test::why(g));
        REQUIRE(g->records.size() == 3);
        CHECK(g->missing_normals == 3);
        REQUIRE(g->shapes.size() == 3);  // the needle makes the file anisotropic
        for (int i = 0; i < 3; ++i) {
            CAPTURE(i);
            const auto& r = g->records[size_t(i)];
            for (int c = 0; c < 3; ++c) {
                CHECK(r.position[c] == doctest::Approx(made[i].p[c]).epsilon(1e-3));  // fixed point, 1/4096 steps
                // 0.5 + Y_0^0 f_dc, then .spz's 8 bits: within 2 of 255.
                const int expected = int(std::lround(std::clamp(0.5f + 0.5f / std::sqrt(k_pi) * made[i].dc[c], 0.0f, 1.0f) * 255.0f));
                CHECK(std::abs(int(r.color[c]) - expected) <= 2);
            }
            CHECK(std::abs(splat::half_to_float(r.opacity_half) - made[i].opacity) < 0.03f);  // opacity stored as a logit in 8 bits: within 0.03
            // Scales in 1/16 of a log unit: within 4 %; the axes as made, rotation included.
            const Eigen::Matrix3f expected_axes = made[i].q.toRotationMatrix() * made[i].scales.asDiagonal();
            const Eigen::Matrix3f cov = splat::shape_axes(g->shapes[size_t(i)]) * splat::shape_axes(g->shapes[size_t(i)]).transpose();
            const Eigen::Matrix3f want = expected_axes * expected_axes.transpose();
            CHECK((cov - want).norm() < 0.1f * want.norm());  // scales in 1/16 of a log unit (4 %), squared
        }
    }

    TEST_CASE("normals a file lacks are estimated: flat Gaussians by their shortest axis, round ones by their neighbours, facing out") {
        // A sphere of 400 Gaussians without normals, written by hand: the even ones round (only
        // the plane through their neighbours can say), the odd ones flat discs tangent to the
        // sphere at a random spin (their own shortest axis says). Both must come out radial.
        const std::string header = header_without_normals(400);
        std::string body;
        std::mt19937 rng(7);
        std::uniform_real_distribution<float> spin(0.0f, 2.0f * k_pi);
        std::vector<Vec3f> points;
        for (int i = 0; i < 400; ++i) {
            // Fibonacci points: about even spacing.
            const float z = 1.0f - 2.0f * (float(i) + 0.5f) / 400.0f, r = std::sqrt(1.0f - z * z), phi = float(i) * 2.39996323f;
            const Vec3f p(2.0f * r * std::cos(phi), 2.0f * r * std::sin(phi), 2.0f * z);  // radius 2
            points.push_back(p);
            const bool flat = i % 2 == 1;
            // The disc's local z turned onto the radial direction, then spun about it.
            const Eigen::Quaternionf q = Eigen::AngleAxisf(spin(rng), p.normalized()) * Eigen::Quaternionf::FromTwoVectors(Vec3f::UnitZ(), p);
            const float thin = flat ? std::log(0.01f) : std::log(0.1f);
            body += floats({p.x(), p.y(), p.z(), 0, 0, 0, 2, std::log(0.1f), std::log(0.1f), thin, q.w(), q.x(), q.y(), q.z()});
        }
        const std::string path = temp("pbdsplat_no_normals.ply");
        write_text(path, header + body);
        auto g = splat::read_ply_gaussians(path, splat::PlyUp::y);
        REQUIRE_MESSAGE(g.ok(), test::why(g));
        REQUIRE(g->records.size() == 400);
        CHECK(g->missing_normals == 400);
        CHECK(g->estimated.from_shape == 200);
        CHECK(g->estimated.from_neighbours == 200);
        CHECK(g->estimated.unresolved == 0);
        // Neighbours 12 deep on a sphere of 400 points see its curvature: a few degrees off
        // radial (measured 3.8 at worst: 10 allowed, and a flipped one is 180); the discs' own axes are exact up to octahedral packing.
        float worst_round = 0.0f, worst_flat = 0.0f;
        for (int i = 0; i < 400; ++i) {
            const float cos_a = splat::decode_octahedral(g->records[i].normal_oct).dot(points[i].normalized());
            const float degrees = std::acos(std::clamp(cos_a, -1.0f, 1.0f)) * 180.0f / k_pi;
            (i % 2 ? worst_flat : worst_round) = std::max(i % 2 ? worst_flat : worst_round, degrees);
        }
        MESSAGE("worst normal error: round " << worst_round << " deg, flat " << worst_flat << " deg");
        CHECK(worst_flat < 0.5f);  // measured 0.028 degrees
        CHECK(worst_round < 10.0f);  // measured 3.8 degrees (a plane through 12 neighbours on a coarse sphere)
        // A torus: on its inner ring the outward side faces the centre, so the sign must travel
        // along the surface (facing away from the centre turns about 40 % inwards; measured 0).
        std::string torus_header = "ply\nformat binary_little_endian 1.0\nelement vertex 1440\n";
        for (const char* name : {"x", "y", "z", "f_dc_0", "f_dc_1", "f_dc_2", "opacity", "scale_0", "scale_1", "scale_2"})
            torus_header += std::string("property float ") + name + "\n";
        torus_header += "end_header\n";
        std::string torus;
        std::vector<Vec3f> outward;
        for (int a = 0; a < 60; ++a)
            for (int b = 0; b < 24; ++b) {
                const float u = 2.0f * k_pi * float(a) / 60.0f, v = 2.0f * k_pi * (float(b) + 0.5f * float(a % 2)) / 24.0f;
                const Vec3f ring(std::cos(u), 0.0f, std::sin(u));
                const Vec3f n = std::cos(v) * ring + std::sin(v) * Vec3f::UnitY();
                const Vec3f p = 2.0f * ring + 0.6f * n;
                outward.push_back(n);
                torus += floats({p.x(), p.y(), p.z(), 0, 0, 0, 2, std::log(0.1f), std::log(0.1f), std::log(0.1f)});
            }
        write_text(path, torus_header + torus);
        auto t = splat::read_ply_gaussians(path, splat::PlyUp::y);
        REQUIRE_MESSAGE(t.ok(), test::why(t));
        CHECK(t->estimated.from_neighbours == 1440);
        int wrong_side = 0;
        float worst_torus = 0.0f;
        for (int i = 0; i < 1440; ++i) {
            const float cos_a = splat::decode_octahedral(t->records[i].normal_oct).dot(outward[i]);
            if (cos_a < 0.0f) ++wrong_side;
            worst_torus = std::max(worst_torus, std::acos(std::clamp(std::abs(cos_a), 0.0f, 1.0f)) * 180.0f / k_pi);
        }
        MESSAGE("torus: " << wrong_side << " facing in, worst " << worst_torus << " deg off the surface normal");
        CHECK(wrong_side == 0);
        CHECK(worst_torus < 10.0f);  // measured 0.11 degrees
        std::filesystem::remove(path);
    }

    TEST_CASE("written for other viewers: y down, the fade in the opacity, no zero colour columns unless asked") {
        splat::Appearance a;
        a.opacity_logit = 3.0f;
        a.scale = 0.05f;
        const std::vector<splat::GaussianRecord> records = {splat::make_record(Vec3f(0.5f, 1.0f, 2.0f), Vec3f::UnitY(), a, 0.5f)};
        const std::string path = temp("pbdsplat_convention.ply");
        REQUIRE(splat::write_ply(path, records).ok());
        CHECK(std::filesystem::file_size(path) == splat::ply_header(1).size() + 17 * sizeof(float));
        std::ifstream in(path, std::ios::binary);
        in.seekg(std::streamoff(splat::ply_header(1).size()));
        float row[17];
        in.read(reinterpret_cast<char*>(row), sizeof(row));
        CHECK(row[0] == 0.5f);
        CHECK(row[1] == -1.0f);  // y down
        CHECK(row[2] == -2.0f);
        CHECK(row[4] == doctest::Approx(-1.0f));  // the normal turns too
        const float seen = 0.5f / (1.0f + std::exp(-3.0f));  // sigmoid(o) times the fade (0.5, as 8 bits)
        CHECK(1.0f / (1.0f + std::exp(-row[9])) == doctest::Approx(seen).epsilon(0.01));
        in.close();
        splat::PlyWriteOptions keep;
        keep.up = splat::PlyUp::y;
        keep.sh_degree = 3;
        REQUIRE(splat::write_ply(path, records, {}, keep).ok());
        CHECK(std::filesystem::file_size(path) == splat::ply_header(1, 3).size() + 62 * sizeof(float));
        auto back = splat::read_ply(path, splat::PlyUp::y);
        REQUIRE(back.ok());
        CHECK(back.value()[0].position[1] == 1.0f);
        std::filesystem::remove(path);
    }

    TEST_CASE("anisotropic shapes survive a round trip; round files carry none") {
        std::mt19937 rng(5);
        std::uniform_real_distribution<float> u(-1.0f, 1.0f), s(0.005f, 0.3f);
        std::vector<splat::GaussianRecord> records;
        std::vector<splat::GaussianShape> shapes;
        std::vector<Eigen::Matrix3f> truth;
        for (int i = 0; i < 200; ++i) {
            const Eigen::Quaternionf q = Eigen::Quaternionf(u(rng), u(rng), u(rng), u(rng)).normalized();
            const Eigen::Matrix3f axes = q.toRotationMatrix() * Vec3f(s(rng), s(rng), s(rng)).asDiagonal();
            splat::Appearance a;
            a.scale = splat::shape_reach(axes);
            records.push_back(splat::make_record(Vec3f(u(rng), u(rng), u(rng)), Vec3f::UnitY(), a));
            shapes.push_back(splat::make_shape(axes));
            truth.push_back(covariance(splat::shape_axes(shapes.back())));  // as stored, in halfs
        }
        const std::string path = temp("pbdsplat_aniso.ply");
        REQUIRE(splat::write_ply(path, records, shapes).ok());
        auto back = splat::read_ply_gaussians(path);
        REQUIRE_MESSAGE(back.ok(), test::why(back));
        REQUIRE(back->shapes.size() == shapes.size());
        for (size_t i = 0; i < shapes.size(); ++i)
            CHECK((covariance(splat::shape_axes(back->shapes[i])) - truth[i]).norm() < 3e-3f * truth[i].norm());
        REQUIRE(splat::write_ply(path, records).ok());  // written round
        auto round = splat::read_ply_gaussians(path);
        REQUIRE(round.ok());
        CHECK(round->shapes.empty());
        std::filesystem::remove(path);
    }

    TEST_CASE("the header is the standard 3DGS layout, byte for byte") {
        std::string expected =
            "ply\nformat binary_little_endian 1.0\nelement vertex 7\nproperty float x\nproperty float y\n"
            "property float z\nproperty float nx\nproperty float ny\nproperty float nz\nproperty float f_dc_0\n"
            "property float f_dc_1\nproperty float f_dc_2\n";
        const std::string tail = "property float opacity\nproperty float scale_0\nproperty float scale_1\nproperty float scale_2\n"
                                 "property float rot_0\nproperty float rot_1\nproperty float rot_2\nproperty float rot_3\nend_header\n";
        CHECK(splat::ply_header(7) == expected + tail);  // degree 0: no f_rest columns
        for (int i = 0; i < 45; ++i) expected += "property float f_rest_" + std::to_string(i) + "\n";
        CHECK(splat::ply_header(7, 3) == expected + tail);
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
        CHECK(std::filesystem::file_size(path) == splat::ply_header(500).size() + 500 * 17 * sizeof(float));
        auto back = splat::read_ply(path);
        REQUIRE_MESSAGE(back.ok(), test::why(back));
        REQUIRE(back->size() == records.size());
        for (size_t i = 0; i < records.size(); ++i) {
            const auto& a = records[i];
            const auto& b = back.value()[i];
            for (int k = 0; k < 3; ++k) CHECK(a.position[k] == b.position[k]);
            for (int k = 0; k < 3; ++k) CHECK(a.color[k] == b.color[k]);
            CHECK(a.opacity_half == b.opacity_half);
            CHECK(std::abs(int(a.scale_half) - int(b.scale_half)) <= 1);  // exp(log(s)): within one half ulp
            CHECK(splat::decode_octahedral(a.normal_oct).dot(splat::decode_octahedral(b.normal_oct)) > 0.99999f);  // octahedral rounding (6.3e-5 rad measured)
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
