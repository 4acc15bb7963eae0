#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "asset/corpus.h"
#include "asset/file_kind.h"
#include "asset/look.h"
#include "asset/mesh_spec.h"
#include "asset/model_file.h"
#include "core/image.h"
#include "mesh/procedural.h"
#include "mesh/repair.h"
#include "support/why.h"

using namespace pbdsplat;

namespace {

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

double area(const mesh::TriangleMesh& m) {
    double a = 0.0;
    for (const auto& t : m.triangles)
        a += 0.5 * double((m.positions[t[1]] - m.positions[t[0]]).cross(m.positions[t[2]] - m.positions[t[0]]).norm());
    return a;
}

// A glTF quad (two triangles) in the xy plane at z = 0, with COLOR_0 and TEXCOORD_0, translated
// by its node; the buffer is the .glb's own.
std::string quad_glb(const std::string& extra_json = "") {
    std::string bin;
    const float pos[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    for (const auto& p : pos)
        for (float x : p) test::put<float>(bin, x);
    const float col[4][3] = {{1, 0, 0}, {1, 0, 0}, {0, 0, 1}, {0, 0, 1}};
    for (const auto& c : col)
        for (float x : c) test::put<float>(bin, x);
    for (int i : {0, 1, 2, 0, 2, 3}) test::put<uint16_t>(bin, uint16_t(i));
    const std::string json = R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],)"
                             R"("nodes":[{"mesh":0,"translation":[0,0,5]}],)"
                             R"("meshes":[{"primitives":[{"attributes":{"POSITION":0,"COLOR_0":1},"indices":2,"material":0}]}],)"
                             R"("materials":[{"pbrMetallicRoughness":{"baseColorFactor":[0.5,1,1,1]}}],)"
                             R"("buffers":[{"byteLength":108}],)"
                             R"("bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":48},{"buffer":0,"byteOffset":48,"byteLength":48},)"
                             R"({"buffer":0,"byteOffset":96,"byteLength":12}],)"
                             R"("accessors":[{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},)"
                             R"({"bufferView":1,"componentType":5126,"count":4,"type":"VEC3"},)"
                             R"({"bufferView":2,"componentType":5123,"count":6,"type":"SCALAR"}])" +
                             extra_json + "}";
    return test::glb(json, bin);
}

} // namespace

TEST_SUITE("asset/model_files") {
    TEST_CASE("content, not the extension, tells a file's kind") {
        test::Corpus c("sniff");
        const auto stl = test::cube_triangles();
        CHECK(asset::sniff_file(c.write("model.txt", test::cube_obj(false))).value() == asset::FileKind::obj);
        CHECK(asset::sniff_file(c.write("a.obj", test::ascii_stl(stl))).value() == asset::FileKind::stl_ascii);
        // A binary STL whose header begins with "solid", as many exporters write it.
        CHECK(asset::sniff_file(c.write("b.stl", test::binary_stl(stl, "solid by a careless exporter"))).value() == asset::FileKind::stl_binary);
        CHECK(asset::sniff_file(c.write("scene.obj", "# a scene\n[model]\nmesh = \"box:2\"\n")).value() == asset::FileKind::scene);
        CHECK(asset::sniff_file(c.write("s.txt", "name = \"x\"\n")).value() == asset::FileKind::scene);
        CHECK(asset::sniff_file(c.write("m.ply", "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nelement face 1\n"
                                                 "property list uchar int vertex_indices\nend_header\n")).value() == asset::FileKind::ply_mesh);
        CHECK(asset::sniff_file(c.write("g.obj", "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\n"
                                                 "property float opacity\nproperty float scale_0\nend_header\n")).value() ==
              asset::FileKind::ply_gaussians);
        CHECK(asset::sniff_file(c.write("q.bin", quad_glb())).value() == asset::FileKind::glb);
        CHECK(asset::sniff_file(c.write("q.json", "  {\"asset\": {\"version\": \"2.0\"}}")).value() == asset::FileKind::gltf);
    }

    TEST_CASE("files that are not models are refused with their name and the reason") {
        test::Corpus c("refuse");
        auto why = [&](const std::string& name, const std::string& bytes) {
            auto r = asset::load_model_file(c.write(name, bytes));
            REQUIRE_FALSE(r.ok());
            const std::string e = r.error().to_string();
            CHECK(contains(e, name));
            return e;
        };
        CHECK(contains(why("utf16.obj", std::string("\xFF\xFEv\0 \0" "0\0", 8)), "UTF-16"));
        CHECK(contains(why("empty.obj", ""), "empty"));
        CHECK(contains(why("cloud.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
                                        "end_header\n0 0 0\n"),
                       "point cloud"));
        CHECK(contains(why("lines.obj", "v 0 0 0\nv 1 0 0\nl 1 2\n"), "no faces"));
        std::string big = "v 0 0 0\nv 1 0 0\nv 1 1 0\nf";
        for (int i = 0; i < 300; ++i) big += " " + std::to_string(1 + i % 3);
        CHECK(contains(why("huge_face.obj", big + "\n"), "at most 255"));
        CHECK(contains(why("noise.bin", std::string("\x01\x02\x00\x7f garbage", 12)), "accepted:"));
        CHECK(contains(why("zip.obj", std::string("PK\x03\x04rest", 8)), "zip"));
        CHECK(contains(why("short.stl", test::binary_stl(test::cube_triangles()).substr(0, 200) + "solid"), "accepted"));
        CHECK(contains(why("trunc.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                                        "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n"),
                       "truncated"));
        CHECK(contains(why("draco.glb", quad_glb(R"(,"extensionsRequired":["KHR_draco_mesh_compression"],"extensionsUsed":["KHR_draco_mesh_compression"])")),
                       "KHR_draco_mesh_compression"));
        CHECK(contains(why("scene.toml", "[model]\nmesh = \"box:2\"\n"), "scene file"));
        CHECK(contains(why("splats.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\nproperty float opacity\nend_header\n"),
                       "Gaussians"));
    }

    TEST_CASE("an STL cube, ASCII or binary, repairs to a closed 8-vertex cube") {
        test::Corpus c("stl");
        const auto corners = test::cube_triangles();
        for (const std::string& path : {c.write("a.stl", test::ascii_stl(corners)), c.write("b.stl", test::binary_stl(corners))}) {
            CAPTURE(path);
            auto a = asset::load_model_file(path);
            REQUIRE_MESSAGE(a.ok(), test::why(a));
            CHECK(a->mesh.triangle_count() == 12);
            CHECK_FALSE(a->look.has_value());
            auto r = mesh::repair(a->mesh, {}, path);
            REQUIRE(r.ok());
            CHECK(r->mesh.vertex_count() == 8);
            CHECK(mesh::is_closed_and_oriented(r->mesh));
            CHECK(mesh::signed_volume(r->mesh) == doctest::Approx(1.0).epsilon(1e-5));
        }
    }

    TEST_CASE("an STL is read z-up unless the scene says y, other files y-up") {
        // A box three times as tall along z as it is wide: as STL (CAD and 3D printing are z-up)
        // it stands along the scene's y; up = y keeps it lying along z, as an OBJ of it does.
        test::Corpus c("up");
        auto corners = test::cube_triangles();
        for (size_t i = 2; i < corners.size(); i += 3) corners[i] *= 3.0f;
        std::string obj;
        for (size_t i = 0; i < corners.size(); i += 3)
            obj += "v " + std::to_string(corners[i]) + " " + std::to_string(corners[i + 1]) + " " + std::to_string(corners[i + 2]) + "\n";
        for (size_t t = 0; t < corners.size() / 9; ++t)
            obj += "f " + std::to_string(3 * t + 1) + " " + std::to_string(3 * t + 2) + " " + std::to_string(3 * t + 3) + "\n";
        const std::string stl = c.write("tall.stl", test::binary_stl(corners)), ascii = c.write("tall_ascii.stl", test::ascii_stl(corners)),
                          plain = c.write("tall.obj", obj);
        auto tallest = [](const std::string& path, asset::UpAxis up) {
            asset::MeshSpecOptions o;
            o.up = up;
            auto m = asset::load_model(path, o);
            REQUIRE_MESSAGE(m.ok(), test::why(m));
            const mesh::Bounds b = mesh::bounds(m->repaired.mesh);
            int axis = 0;
            (b.max - b.min).maxCoeff(&axis);
            return axis;
        };
        CHECK(asset::default_up_axis(asset::FileKind::stl_binary) == asset::UpAxis::z);
        CHECK(asset::default_up_axis(asset::FileKind::glb) == asset::UpAxis::y);
        CHECK(tallest(stl, asset::UpAxis::file_default) == 1);
        CHECK(tallest(ascii, asset::UpAxis::file_default) == 1);
        CHECK(tallest(stl, asset::UpAxis::y) == 2);
        CHECK(tallest(plain, asset::UpAxis::file_default) == 2);
        CHECK(tallest(plain, asset::UpAxis::z) == 1);
    }

    TEST_CASE("a PLY mesh, ASCII and big-endian binary, with sRGB vertex colours") {
        test::Corpus c("ply");
        const std::string head = "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                                 "property uchar red\nproperty uchar green\nproperty uchar blue\n"
                                 "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
        const std::string ascii = "ply\nformat ascii 1.0\n" + head + "0 0 0 255 0 0\n1 0 0 128 0 0\n1 1 0 0 0 0\n0 1 0 0 0 255\n4 0 1 2 3\n";
        std::string big = "ply\nformat binary_big_endian 1.0\n" + head;
        auto put_be = [&](auto v) {
            char b[sizeof v];
            std::memcpy(b, &v, sizeof v);
            for (size_t i = sizeof v; i-- > 0;) big += b[i];
        };
        const float xyz[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
        const uint8_t rgb[4][3] = {{255, 0, 0}, {128, 0, 0}, {0, 0, 0}, {0, 0, 255}};
        for (int v = 0; v < 4; ++v) {
            for (float x : xyz[v]) put_be(x);
            for (uint8_t k : rgb[v]) big += char(k);
        }
        big += char(4);
        for (int32_t i : {0, 1, 2, 3}) put_be(i);
        for (const std::string& path : {c.write("a.ply", ascii), c.write("b.ply", big)}) {
            CAPTURE(path);
            auto a = asset::load_model_file(path);
            REQUIRE_MESSAGE(a.ok(), test::why(a));
            CHECK(a->mesh.vertex_count() == 4);
            CHECK(a->mesh.triangle_count() == 2);
            CHECK(area(a->mesh) == doctest::Approx(1.0));
            REQUIRE(a->look.has_value());
            // Vertex 1 (128 as sRGB) is 0.2158 linear, wherever it is a corner.
            const auto& tri = a->mesh.triangles[0];
            for (int k = 0; k < 3; ++k)
                if (tri[size_t(k)] == 1) CHECK(a->look->corner_color[0][size_t(k)].x() == doctest::Approx(0.2158).epsilon(1e-3));
        }
    }

    TEST_CASE("a glTF binary: node transform, base colour factor times vertex colour") {
        test::Corpus c("glb");
        auto a = asset::load_model_file(c.write("quad.glb", quad_glb()));
        REQUIRE_MESSAGE(a.ok(), test::why(a));
        CHECK(a->mesh.vertex_count() == 4);
        CHECK(a->mesh.triangle_count() == 2);
        for (const Vec3f& p : a->mesh.positions) CHECK(p.z() == doctest::Approx(5.0f));  // the node's translation
        REQUIRE(a->look.has_value());
        // Corner 0 is red, the factor halves red: (0.5, 0, 0). glTF vertex colours are linear.
        const Vec3f c0 = a->look->color_at(0, Vec2f(0, 0));
        CHECK(c0.x() == doctest::Approx(0.5f));
        CHECK(c0.z() == doctest::Approx(0.0f));
    }

    TEST_CASE("texture lookups against hand-computed texels: bilinear, sRGB, wrap modes") {
        asset::Texture t;
        t.width = 2, t.height = 2;
        t.rgba = {255, 0, 0, 255, 0, 255, 0, 255,  // top row: red, green
                  0, 0, 255, 255, 128, 128, 128, 255};  // bottom row: blue, grey 128
        auto near = [](const Vec3f& a, const Vec3f& b) { return (a - b).cwiseAbs().maxCoeff() < 1e-4f; };
        CHECK(near(t.sample(Vec2f(0.25f, 0.25f)), Vec3f(1, 0, 0)));              // a texel centre
        CHECK(near(t.sample(Vec2f(0.5f, 0.25f)), Vec3f(0.5f, 0.5f, 0)));         // between red and green
        const float g = asset::srgb_to_linear(uint8_t(128));
        CHECK(g == doctest::Approx(0.21586f).epsilon(1e-3));
        CHECK(near(t.sample(Vec2f(0.75f, 0.75f)), Vec3f(g, g, g)));               // decoded, not 0.5
        // u = 0 lies half a texel left of the first centre.
        CHECK(near(t.sample(Vec2f(0.0f, 0.25f)), Vec3f(0.5f, 0.5f, 0)));         // repeat: the last texel wraps in
        t.wrap_u = asset::Wrap::clamp;
        CHECK(near(t.sample(Vec2f(0.0f, 0.25f)), Vec3f(1, 0, 0)));
        CHECK(near(t.sample(Vec2f(1e9f, 0.25f)), Vec3f(0, 1, 0)));               // far out: the edge texel
        t.wrap_u = asset::Wrap::mirror;
        CHECK(near(t.sample(Vec2f(0.0f, 0.25f)), Vec3f(1, 0, 0)));                // mirrored: the first texel again
        CHECK(near(t.sample(Vec2f(1.25f, 0.25f)), Vec3f(0, 1, 0)));               // 1.25 mirrors to 0.75
    }

    TEST_CASE("an OBJ with its MTL: Kd per material, map_Kd through a Windows path") {
        test::Corpus c("mtl");
        core::ImageRgba8 img(2, 1);
        const uint8_t px[8] = {255, 255, 255, 255, 0, 0, 0, 255};  // white, black
        std::copy(px, px + 8, img.pixels.begin());
        REQUIRE(core::write_png(c.path("maps/stripes.png"), img).ok() == false);  // its folder does not exist yet
        c.write("maps/.keep", "");
        REQUIRE(core::write_png(c.path("maps/stripes.png"), img).ok());
        c.write("cube.mtl", "newmtl side\nKd 0 0 1\nnewmtl top\nKd 1 1 1\nmap_Kd maps\\stripes.png\n");
        std::string obj = test::cube_obj(true);
        // The top face gets texture coordinates: u from 0 to 1 across it.
        obj.replace(obj.find("f 3 4 8 7"), 9, "vt 0.75 0.5\nvt 0.25 0.5\nf 3/1 4/2 8/2 7/1");
        auto a = asset::load_model_file(c.write("cube.obj", obj));
        REQUIRE_MESSAGE(a.ok(), test::why(a));
        CHECK(a->warnings.empty());
        REQUIRE(a->look.has_value());
        const asset::SurfaceLook& look = *a->look;
        REQUIRE(look.textures.size() == 1);
        CHECK(look.textures[0].width == 2);
        // A side triangle is blue; the top's corners at u = 0.75 read black, at 0.25 white.
        CHECK(look.color_at(0, Vec2f(0.3f, 0.3f)).isApprox(Vec3f(0, 0, 1)));
        const size_t top = a->mesh.triangle_count() - 1;
        const auto& tri = a->mesh.triangles[top];
        for (int k = 0; k < 3; ++k) {
            const Vec2f b = k == 0 ? Vec2f(0, 0) : k == 1 ? Vec2f(1, 0) : Vec2f(0, 1);
            const bool at_u75 = tri[size_t(k)] == 2 || tri[size_t(k)] == 6;  // vertices 3 and 7 (1-based)
            CHECK(look.color_at(uint32_t(top), b).x() == doctest::Approx(at_u75 ? 0.0f : 1.0f));
        }
    }

    TEST_CASE("a missing texture loads the model with its colour and a warning") {
        test::Corpus c("missing");
        c.write("cube.mtl", "newmtl side\nKd 0 1 0\nnewmtl top\nKd 1 0 0\nmap_Kd C:\\Users\\someone\\gone.jpg\n");
        auto a = asset::load_model_file(c.write("cube.obj", test::cube_obj(true)));
        REQUIRE(a.ok());
        REQUIRE(a->warnings.size() == 1);
        CHECK(contains(a->warnings[0], "gone.jpg"));
        REQUIRE(a->look.has_value());
        CHECK(a->look->color_at(0, Vec2f(0.3f, 0.3f)).isApprox(Vec3f(0, 1, 0)));
    }

    TEST_CASE("a concave polygon keeps its notch") {
        // An L of area 3 (a 2 x 2 square less one unit square) as one face; a fan from its
        // first corner would cover the notch.
        const std::string obj = "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\nf 1 2 3 4 5 6\n";
        test::Corpus c("concave");
        auto a = asset::load_model_file(c.write("l.obj", obj));
        REQUIRE(a.ok());
        CHECK(a->mesh.triangle_count() == 4);
        CHECK(area(a->mesh) == doctest::Approx(3.0));
        // A ring joined by a bridge: the outer square 0..3 and the inner 1..2, area 9 - 1.
        const std::string ring = "v 0 0 0\nv 3 0 0\nv 3 3 0\nv 0 3 0\nv 1 1 0\nv 1 2 0\nv 2 2 0\nv 2 1 0\n"
                                 "f 1 2 3 4 1 5 6 7 8 5\n";
        auto r = asset::load_model_file(c.write("ring.obj", ring));
        REQUIRE(r.ok());
        CHECK(area(r->mesh) == doctest::Approx(8.0));
    }

    TEST_CASE("a tiny model is refined before it is simulated") {
        test::Corpus c("tiny");
        const std::string path = c.write("cube.obj", test::cube_obj(false));
        auto m = asset::load_model(path);
        REQUIRE(m.ok());
        CHECK(m->refined_levels > 0);
        const mesh::TriangleMesh& cube = m->repaired.mesh;
        CHECK(cube.vertex_count() >= asset::k_min_file_vertices);
        CHECK(mesh::is_closed_and_oriented(cube));
        // Still a cube: flat faces, the same volume.
        const double side = 2.0 / std::sqrt(3.0);  // fitted to a diagonal of 2
        CHECK(mesh::signed_volume(cube) == doctest::Approx(side * side * side).epsilon(1e-4));
    }

    TEST_CASE("a low-poly part of a larger model is refined; the model's fine part and the shared models are not") {
        // A fine ball (642 vertices, past k_min_file_vertices) beside an 8-vertex box: as a whole
        // the file is not tiny, but the box alone would be eight particles lit as a ball.
        const mesh::TriangleMesh ball = mesh::icosphere(3);
        std::string obj;
        for (const Vec3f& p : ball.positions) obj += "v " + std::to_string(p.x()) + " " + std::to_string(p.y()) + " " + std::to_string(p.z()) + "\n";
        for (int k = 0; k < 8; ++k) obj += "v " + std::to_string(3 + (k & 1)) + " " + std::to_string((k >> 1) & 1) + " " + std::to_string((k >> 2) & 1) + "\n";
        for (const mesh::Triangle& t : ball.triangles) obj += "f " + std::to_string(t[0] + 1) + " " + std::to_string(t[1] + 1) + " " + std::to_string(t[2] + 1) + "\n";
        const size_t o = ball.vertex_count() + 1;
        const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
        for (const auto& f : faces) obj += "f " + std::to_string(o + f[0]) + " " + std::to_string(o + f[1]) + " " + std::to_string(o + f[2]) + " " + std::to_string(o + f[3]) + "\n";
        test::Corpus c("lowpoly_part");
        auto m = asset::load_model(c.write("ball_and_box.obj", obj));
        REQUIRE(m.ok());
        CHECK(m->refined_levels == 2);
        CHECK(m->repaired.mesh.triangle_count() == ball.triangle_count() + 12 * 16);
        CHECK(mesh::is_closed_and_oriented(m->repaired.mesh));
        // The shared models keep their own resolution (suzanne's eyes, the coarsest part there,
        // reach 0.30 of their size).
        for (const char* name : {"suzanne.obj", "teapot.obj"}) {
            auto shared = asset::load_model(name);
            if (!shared.ok()) continue;  // not installed: nothing to hold
            CHECK_MESSAGE(shared->refined_levels == 0, name);
        }
    }
}

TEST_SUITE("asset/model_files") {
    TEST_CASE("a texture named by its author's absolute Windows path is found beside the model, whatever its case") {
        test::Corpus c("authorpath");
        c.write("Textures/.keep", "");
        core::ImageRgba8 img(1, 1);
        img.pixels = {0, 255, 0, 255};
        REQUIRE(core::write_png(c.path("Textures/skin.png"), img).ok());
        c.write("cube.mtl", "newmtl side\nKd 1 0 0\nnewmtl top\nKd 1 1 1\nmap_Kd -s 1 1 1 C:\\Users\\artist\\Desktop\\TEXTURES\\Skin.PNG\n");
        std::string obj = test::cube_obj(true);
        obj.replace(obj.find("f 3 4 8 7"), 9, "vt 0.5 0.5\nf 3/1 4/1 8/1 7/1");
        auto a = asset::load_model_file(c.write("cube.obj", obj));
        REQUIRE(a.ok());
        CHECK(a->warnings.empty());
        REQUIRE(a->look.has_value());
        REQUIRE(a->look->textures.size() == 1);
        const size_t top = a->mesh.triangle_count() - 1;
        CHECK(a->look->color_at(uint32_t(top), Vec2f(0.3f, 0.3f)).isApprox(Vec3f(0, 1, 0)));
    }
}
