#include <doctest/doctest.h>

#include <filesystem>

#include <string>

#include "asset/mesh_spec.h"
#include "asset/obj_loader.h"

using namespace pbdsplat;

namespace {
// The error of a text that must be refused, as "file:line: message".
std::string refusal(const std::string& text) {
    auto r = asset::parse_obj(text, "broken.obj");
    REQUIRE_FALSE(r.ok());
    return r.error().to_string();
}
} // namespace

TEST_SUITE("asset/obj_loader") {
    TEST_CASE("a quad with normals, UVs and colours loads as two triangles") {
        const std::string text =
            "# quad\n"
            "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 1 1 0 0 0 1\nv 0 1 0 1 1 1\n"
            "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
            "vn 0 0 1\n"
            "f 1/1/1 2/2/1 3/3/1 4/4/1\n";
        auto m = asset::parse_obj(text, "quad.obj");
        REQUIRE(m.ok());
        CHECK(m->positions.size() == 4);
        CHECK(m->triangles.size() == 2);
        REQUIRE(m->colors.size() == 4);
        CHECK(m->colors[1].y() == 1.0f);
        REQUIRE(m->uvs.size() == 4);
        CHECK(m->uvs[2] == Vec2f(1, 1));
        REQUIRE(m->normals.size() == 4);
        CHECK(m->normals[0].z() == 1.0f);
    }

    TEST_CASE("negative (relative) indices are resolved") {
        auto m = asset::parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n", "rel.obj");
        REQUIRE(m.ok());
        CHECK(m->triangles[0] == mesh::Triangle{0, 1, 2});
    }

    TEST_CASE("broken files are refused with the file, the line and the problem") {
        CHECK(refusal("v 0 0 0\nv 1 0 zero\n") == "broken.obj:2: 'zero' is not a number");
        CHECK(refusal("v 0 0\n") == "broken.obj:1: vertex 'v' needs 3 to 7 numbers, found 2");
        CHECK(refusal("v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 4\n") ==
              "broken.obj:5: face refers to vertex 4, but only 3 are defined above this line");
        CHECK(refusal("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n") == "broken.obj:4: face index 0 is invalid (OBJ indices start at 1)");
        CHECK(refusal("v 0 0 0\nv 1 0 0\nf 1 2\n") == "broken.obj:3: face 'f' needs at least 3 vertices, found 2");
        CHECK(refusal("v 0 0 nan\n").find("broken.obj:1: vertex 'v' has a non-finite value") == 0);
        CHECK(refusal("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/9 2 3\n").find("broken.obj:4: face refers to texture coordinate 9") == 0);
        CHECK(refusal("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n") == "broken.obj:4: face index 'x' is not an integer");
        CHECK(refusal("# nothing\n") == "broken.obj: no vertices ('v' lines)");
        CHECK(refusal("v 0 0 0\nv 1 0 0\nv 0 1 0\n") == "broken.obj: no faces ('f' lines): nothing to simulate or render");
    }

    TEST_CASE("a missing file names the path") {
        auto r = asset::load_obj("/nonexistent/model.obj");
        REQUIRE_FALSE(r.ok());
        CHECK(r.error().to_string().find("/nonexistent/model.obj") == 0);
    }

    TEST_CASE("a folder given as a mesh is named as a folder, not as a missing file") {
        const std::string dir = std::filesystem::temp_directory_path().string();
        auto r = asset::load_obj(dir);
        REQUIRE_FALSE(r.ok());
        CHECK(r.error().message == "is a folder, not an .obj file");
        auto spec = asset::load_mesh_spec(dir);
        REQUIRE_FALSE(spec.ok());
        CHECK(spec.error().message.find("is a folder, not a mesh file") != std::string::npos);
    }
}
