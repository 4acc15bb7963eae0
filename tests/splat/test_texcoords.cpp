#include <doctest/doctest.h>

#include <cmath>

#include "asset/surface_colors.h"
#include "asset/texture_charts.h"
#include "core/half.h"
#include "splat/texcoords.h"

using namespace pbdsplat;

namespace {

Vec3f gradient_half(const splat::GaussianTexcoord& t, int first) {
    return Vec3f(core::half_to_float(t.gradient_half[first]), core::half_to_float(t.gradient_half[first + 1]),
                 core::half_to_float(t.gradient_half[first + 2]));
}

// A strip of two unit squares along x at z = 0, four triangles, texture coordinates (x / 2, y),
// except that `split` gives the second square's corners on the shared edge their own vertices
// with u shifted by `shift` (a seam where the shift is not a whole repeat).
asset::SurfaceLook strip(bool split, float shift, asset::Wrap wrap) {
    asset::SurfaceLook look;
    look.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0}, {2, 1, 0}, {1, 0, 0}, {1, 1, 0}};
    const uint32_t a = split ? 6u : 1u, b = split ? 7u : 2u;
    look.triangles = {{0, 1, 2}, {0, 2, 3}, {a, 4, 5}, {a, 5, b}};
    for (size_t t = 0; t < look.triangles.size(); ++t) {
        std::array<Vec2f, 3> uv;
        for (int k = 0; k < 3; ++k) {
            const Vec3f& p = look.positions[look.triangles[t][k]];
            uv[size_t(k)] = Vec2f(p.x() / 2.0f + (t >= 2 && split ? shift : 0.0f), p.y());
        }
        look.uv.push_back(uv);
    }
    look.material = {0, 0, 0, 0};
    asset::Material m;
    m.texture = 0;
    look.materials = {m};
    asset::Texture texture;
    texture.width = texture.height = 1;
    texture.rgba = {255, 255, 255, 255};
    texture.wrap_u = texture.wrap_v = wrap;
    look.textures = {texture};
    return look;
}

} // namespace

TEST_SUITE("splat/texcoords") {
    TEST_CASE("a triangle's coordinate gradients are exact, and none for a degenerate one") {
        asset::SurfaceLook look;
        // u = 2x + y, v = 3z over a triangle in the plane y = x (normal (1, -1, 0) / sqrt 2).
        look.positions = {{0, 0, 0}, {1, 1, 0}, {0, 0, 1}, {1, 1, 1}};
        look.triangles = {{0, 1, 2}, {0, 1, 3}};
        const auto uv = [](const Vec3f& p) { return Vec2f(2 * p.x() + p.y(), 3 * p.z()); };
        for (const mesh::Triangle& t : look.triangles)
            look.uv.push_back({uv(look.positions[t[0]]), uv(look.positions[t[1]]), uv(look.positions[t[2]])});
        const auto g = asset::uv_gradient(look, 0);
        REQUIRE(g.has_value());
        // In the plane: (2, 1, 0) less its part along the normal, which is (0.5, -0.5, 0).
        CHECK(g->du.isApprox(Vec3f(1.5f, 1.5f, 0.0f), 1e-5f));
        CHECK(g->dv.isApprox(Vec3f(0.0f, 0.0f, 3.0f), 1e-5f));
        look.uv[1] = {Vec2f(0, 0), Vec2f(0, 0), Vec2f(0, 0)};  // every corner at one texel
        CHECK_FALSE(asset::uv_gradient(look, 1).has_value());
    }

    TEST_CASE("seams are where one point takes two places of the texture; whole repeats of a wrapped texture are none") {
        const asset::TextureCharts joined(strip(false, 0.0f, asset::Wrap::clamp));
        CHECK(joined.seam_vertices() == 0);
        CHECK_FALSE(joined.near_seam(Vec3f(1, 0.5f, 0), 0.5f));

        const asset::TextureCharts seam(strip(true, 0.25f, asset::Wrap::clamp));
        CHECK(seam.seam_vertices() == 2);
        CHECK(seam.near_seam(Vec3f(1.2f, 0.5f, 0), 0.6f));       // the shared edge's corners within reach
        CHECK_FALSE(seam.near_seam(Vec3f(1.8f, 0.5f, 0), 0.6f));  // out of reach
        CHECK_FALSE(seam.near_seam(Vec3f(0.2f, 0.5f, 0), 0.6f));

        CHECK(asset::TextureCharts(strip(true, 1.0f, asset::Wrap::repeat)).seam_vertices() == 0);
        CHECK(asset::TextureCharts(strip(true, 1.0f, asset::Wrap::clamp)).seam_vertices() == 2);
    }

    TEST_CASE("a point of a textured surface reads its coordinates, gradients, tint, and how far it may read short of a seam") {
        asset::SurfaceLook look = strip(true, 0.25f, asset::Wrap::clamp);
        look.materials[0].color = Vec3f(0.5f, 1.0f, 1.0f);
        const asset::SurfaceColors colors(std::move(look));
        std::vector<mesh::ClosestPoint> scratch;
        const auto far = colors.texture_point(Vec3f(0.3f, 0.4f, 0.01f), 0.2f, scratch);
        REQUIRE(far.has_value());
        CHECK(far->texture == 0);
        CHECK(far->uv.isApprox(Vec2f(0.15f, 0.4f), 1e-5f));
        CHECK(far->gradient.du.isApprox(Vec3f(0.5f, 0, 0), 1e-5f));
        CHECK(far->gradient.dv.isApprox(Vec3f(0, 1, 0), 1e-5f));
        CHECK(far->tint.isApprox(Vec3f(0.5f, 1.0f, 1.0f)));
        CHECK(far->reach == 0.2f);  // no seam within reach: all of it
        const auto near = colors.texture_point(Vec3f(0.9f, 0.4f, 0.0f), 0.2f, scratch);  // the seam at x = 1
        REQUIRE(near.has_value());
        // 0.1 from the seam, never read past it: within the spacing of the seam's points (a tenth of an edge).
        CHECK(near->reach <= 0.1f);
        CHECK(near->reach > 0.04f);  // the seams points lie a tenth of an edge apart (0.04 here)
    }

    TEST_CASE("a sample's gradients turn and stretch with its triangle, its coordinates stay") {
        // One triangle at rest in the xy plane; now turned a quarter about z and stretched to
        // twice its length along its first edge.
        const std::vector<Vec3f> rest = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
        const std::vector<Vec4f> now = {{0, 0, 0, 0}, {0, 2, 0, 0}, {-1, 0, 0, 0}};
        const std::vector<mesh::Triangle> triangles = {{0, 1, 2}};
        surface::BoundaryParticles samples;
        samples.triangle = {0, 0};
        samples.bary = {Vec2f(0.2f, 0.3f), Vec2f(0.5f, 0.1f)};
        surface::BoundaryParticles::Texcoord c;
        c.uv = Vec2f(0.3f, 0.7f);
        c.du = Vec3f(4, 0, 0);  // u = 4x at rest
        c.dv = Vec3f(0, 4, 0);
        c.tint = Vec3f(1.0f, 0.5f, 0.25f);
        c.texture = 2;
        c.reach = 0.125f;
        samples.texcoord = {c, surface::BoundaryParticles::Texcoord{}};  // the second: no texture
        std::vector<splat::GaussianTexcoord> out;
        splat::TexcoordScratch scratch;
        // Three particles' records first (the last textured, the others not), the two samples',
        // then a cut face's.
        std::vector<mesh::SurfaceTexcoord> particles(3);
        particles[2] = c;
        particles[2].uv = Vec2f(0.9f, 0.1f);
        splat::map_texcoords(rest, now, triangles, 3, particles, samples, 6, out, scratch);
        REQUIRE(out.size() == 6);
        for (size_t i : {0, 1, 4, 5}) CHECK(out[i].texture == SPLAT_NO_TEXTURE);
        CHECK(out[2].texture == 2);
        CHECK(out[2].uv[0] == 0.9f);
        CHECK(gradient_half(out[2], 0).isApprox(Vec3f(0, 2, 0), 1e-3f));
        const splat::GaussianTexcoord& t = out[3];
        CHECK(t.texture == 2);
        CHECK(t.uv[0] == 0.3f);
        CHECK(t.uv[1] == 0.7f);
        // Rest x now runs along +y at twice the length: u changes by 2 per unit of y; rest y now
        // runs along -x: v changes by -4 per unit of x.
        CHECK(gradient_half(t, 0).isApprox(Vec3f(0, 2, 0), 1e-3f));
        CHECK(gradient_half(t, 3).isApprox(Vec3f(-4, 0, 0), 1e-3f));
        CHECK(t.tint[0] == 255);
        CHECK(t.tint[1] == 128);
        CHECK(t.tint[2] == 64);
        CHECK(core::half_to_float(t.reach_half) == 0.125f);
    }
}
