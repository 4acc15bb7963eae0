#include <doctest/doctest.h>

#include <memory>

#include "mesh/procedural.h"
#include "scene/stages/mapping_stage.h"
#include "scene/stages/paint.h"

using namespace pbdsplat;

namespace {

// A unit square at z = 0 in two triangles, texture coordinates its own (x, y), material colour
// `tint` times texture 0 (2x2 texels).
asset::SurfaceLook square_look(const Vec3f& tint) {
    asset::SurfaceLook look;
    look.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    look.triangles = {{0, 1, 2}, {0, 2, 3}};
    for (const mesh::Triangle& t : look.triangles)
        look.uv.push_back({look.positions[t[0]].head<2>(), look.positions[t[1]].head<2>(), look.positions[t[2]].head<2>()});
    look.material = {0, 0};
    asset::Material m;
    m.color = tint;
    m.texture = 0;
    look.materials = {m};
    asset::Texture texture;
    texture.name = "checker";
    texture.width = texture.height = 2;
    texture.rgba = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 255};
    look.textures = {texture};
    return look;
}

} // namespace

TEST_SUITE("scene/paint") {
    TEST_CASE("triangles take the texture, coordinates and tint of the model's surface where they lie") {
        scene::SurfacePaint paint;
        paint.model = {std::make_shared<const asset::SurfaceColors>(square_look(Vec3f(0.5f, 1.0f, 1.0f)))};
        paint.plain = {Vec3f::Ones()};
        // The model's own two triangles, and one inside the first that is not the model's: its
        // corners read the look where they stand.
        const std::vector<Vec3f> rest = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5f, 0.1f, 0}, {0.9f, 0.2f, 0}, {0.8f, 0.6f, 0}};
        const std::vector<mesh::Triangle> triangles = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}};
        const scene::TriangleLooks looks = scene::paint_triangles(paint, rest, {}, triangles);
        REQUIRE(looks.textures.size() == 1);
        CHECK(looks.textures[0]->name == "checker");
        REQUIRE(looks.texture.size() == 3);
        for (size_t t = 0; t < triangles.size(); ++t) {
            CHECK(looks.texture[t] == 0);
            for (int k = 0; k < 3; ++k) {
                const Vec3f& p = rest[triangles[t][k]];
                CHECK(looks.uv[t][k].x() == doctest::Approx(p.x()).epsilon(1e-5));
                CHECK(looks.uv[t][k].y() == doctest::Approx(p.y()).epsilon(1e-5));
                CHECK(looks.tint[t][k].isApprox(Vec3f(0.5f, 1.0f, 1.0f)));
            }
        }
    }

    TEST_CASE("each model's textures follow the models before it's; a plain look gives no textures") {
        scene::SurfacePaint paint;
        paint.model = {std::make_shared<const asset::SurfaceColors>(square_look(Vec3f::Ones())),
                       std::make_shared<const asset::SurfaceColors>(square_look(Vec3f(1.0f, 0.2f, 0.2f)))};
        paint.plain = {Vec3f::Ones(), Vec3f::Ones()};
        const std::vector<Vec3f> rest = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}};
        const std::vector<uint32_t> model = {0, 0, 0, 1, 1, 1};
        const std::vector<mesh::Triangle> triangles = {{0, 1, 2}, {3, 4, 5}};
        const scene::TriangleLooks looks = scene::paint_triangles(paint, rest, model, triangles);
        REQUIRE(looks.textures.size() == 2);
        CHECK(looks.texture[0] == 0);
        CHECK(looks.texture[1] == 1);
        CHECK(looks.tint[1][0].isApprox(Vec3f(1.0f, 0.2f, 0.2f)));

        scene::SurfacePaint plain;
        plain.model = {nullptr};
        plain.plain = {Vec3f(0.3f, 0.3f, 0.3f)};
        CHECK(scene::paint_triangles(plain, rest, {}, triangles).textures.empty());
    }

    TEST_CASE("once a frame drew textured splats, a frame without them hands over an untextured entry for every record") {
        auto made = sim::make_soft_body(mesh::icosphere(1), {});
        REQUIRE(made.ok());
        const sim::SoftBody& body = made.value();
        const mesh::TriangleMesh rest{body.rest_positions, body.triangles, {}, {}, {}};
        surface::BoundaryParticles samples = surface::sample_surface(rest, {surface::spacing(rest, 0.5f), 1});
        surface::update_boundary_particles(body.triangles, body.particles.x, body.normals, samples);
        REQUIRE(samples.size() > 0);
        surface::BoundaryParticles::Texcoord c;
        c.du = Vec3f(1, 0, 0);
        c.dv = Vec3f(0, 1, 0);
        c.texture = 0;
        c.reach = 0.1f;
        samples.texcoord.assign(samples.size(), c);
        scene::MappingStage mapping(body, 0, false, false);
        scene::MappingStage::Sources sources;
        sources.body = &body;
        sources.samples = &samples;
        const splat::Appearance look;
        mapping.map(sources, look);
        REQUIRE(mapping.texcoords().size() == mapping.records().size());
        CHECK(mapping.texcoords().back().texture == 0);
        // The user hides the boundary splats: the renderer still reads an entry per record.
        sources.samples = nullptr;
        mapping.map(sources, look);
        REQUIRE(mapping.texcoords().size() == mapping.records().size());
        for (const splat::GaussianTexcoord& t : mapping.texcoords()) CHECK(t.texture == SPLAT_NO_TEXTURE);
    }
}
