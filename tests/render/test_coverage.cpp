#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <random>

#include "asset/look.h"
#include "asset/mesh_spec.h"
#include "mesh/procedural.h"
#include "asset/model_path.h"
#include "passes/coverage.h"
#include "passes/offscreen_renderer.h"
#include "scene/stages/paint.h"
#include "splat/sort.h"
#include "splat/texcoords.h"
#include "sim/soft_body.h"
#include "splat/mapping.h"
#include "surface/density.h"
#include "surface/thin_order.h"
#include "support/gpu_fixture.h"

#include "support/skip.h"
#include "support/why.h"
using namespace pbdsplat;

namespace {
struct Result2 {
    passes::Coverage boundary, vertices;
};

// The rest state of a mesh rendered twice at the same splat size: with boundary particles
// (eta = 0.5) and with the mesh vertices alone (the paper's Figure 14a baseline). The Gaussian
// is sized small enough that the vertices alone cannot close the surface; the paper's disc at
// the scenes' sizing (s0 = 0.7 h, the closing kappa).
Result2 coverage_of(gpu::Context& ctx, const std::string& spec, render::Footprint footprint) {
    auto repaired = asset::load_mesh_spec(spec);
    REQUIRE_MESSAGE(repaired.ok(), test::why(repaired));
    auto body = sim::make_soft_body(repaired->mesh, {});
    REQUIRE(body.ok());
    const mesh::TriangleMesh rest{body->rest_positions, body->triangles, {}, {}, {}};
    const float h = surface::spacing(rest, 0.5f);
    const auto samples = surface::sample_surface(rest, {h, 1});
    splat::Appearance look;
    look.scale = (footprint == render::Footprint::paper ? 0.7f : 0.6f) * h;
    std::vector<splat::GaussianRecord> with, without;
    splat::map_body(body->particles.x, body->normals, {}, body->triangles, &samples, look, nullptr, nullptr, with);
    splat::map_body(body->particles.x, body->normals, {}, body->triangles, nullptr, look, nullptr, nullptr, without);

    const mesh::Bounds b = mesh::bounds(rest);
    render::FrameInputs frame;
    frame.style.footprint = footprint;
    frame.camera.target = b.center();
    frame.camera.eye = b.center() + Vec3f(0.3f, 0.35f, 1.1f) * b.diagonal();
    std::vector<std::array<uint32_t, 3>> tris(body->triangles.begin(), body->triangles.end());
    auto a = passes::measure_coverage(ctx, body->particles.x, tris, with, frame, 256, 256);
    auto v = passes::measure_coverage(ctx, body->particles.x, tris, without, frame, 256, 256);
    REQUIRE_MESSAGE(a.ok(), test::why(a));
    REQUIRE_MESSAGE(v.ok(), test::why(v));
    MESSAGE(spec << ", " << std::string(render::footprint_name(footprint)) << ": " << with.size() << " splats with boundary particles: hole ratio " << a->hole_ratio * 100.0
                 << " %, IoU " << a->silhouette_iou << "; " << without.size() << " vertex-only: hole ratio "
                 << v->hole_ratio * 100.0 << " %, IoU " << v->silhouette_iou);
    return {std::move(a).value(), std::move(v).value()};
}
// A lumpy sphere at rest, its boundary particles and the frame both lumpy-sphere tests draw:
// every disc spans a curved patch.
struct LumpySphere {
    sim::SoftBody body;
    surface::BoundaryParticles samples;
    splat::Appearance look;
    splat::NormalField field;
    render::FrameInputs frame;
    std::vector<std::array<uint32_t, 3>> triangles;
    const Vec3f albedo{0.8f, 0.4f, 0.3f};

    LumpySphere() {
        mesh::TriangleMesh lumpy = mesh::icosphere(3, 1.0f);
        for (Vec3f& p : lumpy.positions) p *= 1.0f + 0.08f * std::sin(6.0f * p.x()) * std::cos(5.0f * p.y());
        auto made = sim::make_soft_body(lumpy, {});
        REQUIRE(made.ok());
        body = std::move(made).value();
        const mesh::TriangleMesh rest{body.rest_positions, body.triangles, {}, {}, {}};
        const float h = surface::spacing(rest, 0.5f);
        samples = surface::sample_surface(rest, {h, 1});
        surface::update_boundary_particles(body.triangles, body.particles.x, body.normals, samples);
        look.scale = 0.7f * h;
        look.albedo = albedo;
        field.update(body.particles.x, body.normals, body.triangles, true, splat::curvature_limit(look.scale));
        frame.style.footprint = render::Footprint::paper;
        // The key light alone: the environment's lookups differ between the splat and mesh renderers.
        frame.lighting.environment.sampling = render::EnvSampling::off;
        frame.camera.target = Vec3f::Zero();
        frame.camera.eye = Vec3f(0.9f, 1.0f, 3.2f);
        triangles.assign(body.triangles.begin(), body.triangles.end());
    }
    std::vector<splat::GaussianRecord> records(bool turning) const {
        std::vector<splat::GaussianRecord> out;
        splat::map_body(body.particles.x, body.normals, {}, body.triangles, &samples, look, nullptr, turning ? &field : nullptr, out);
        return out;
    }
    core::Result<passes::Coverage> draw(gpu::Context& ctx, std::span<const splat::GaussianRecord> records, const render::FrameInputs& f,
                                        uint32_t size = 256) const {
        return passes::measure_coverage(ctx, body.particles.x, triangles, records, f, size, size, albedo);
    }
};
} // namespace

TEST_SUITE("render/coverage") {
    TEST_CASE("boundary particles close the surface where vertices alone leave holes: icosphere") {
        auto ctx = test::open_validated_context();
        const auto c = coverage_of(*ctx, "icosphere:3", render::Footprint::gaussian);
        CHECK(c.boundary.mesh_pixels > 10000);
        CHECK(c.boundary.hole_ratio < 0.005);  // the hole goal, 0.5 %; measured 0
        // Vertices alone miss the project's hole goal (0.5 %); boundary particles meet it.
        CHECK(c.vertices.hole_ratio > 4.0 * c.boundary.hole_ratio + 0.005);
        CHECK(c.boundary.silhouette_iou > 0.8);  // the splats reach about one sigma past the silhouette
        // The paper's disc at its closing size: no holes, and a silhouette as tight.
        const auto d = coverage_of(*ctx, "icosphere:3", render::Footprint::paper);
        CHECK(d.boundary.hole_ratio < 0.005);  // the hole goal; measured 0
        CHECK(d.boundary.silhouette_iou > 0.8);  // measured 0.83
        test::require_no_validation_messages(*ctx);
    }

    TEST_CASE("boundary particles close the surface where vertices alone leave holes: teapot") {
        if (!asset::find_model("teapot.obj")) {
            test::skip("teapot.obj not found on the model search path (../shared/models)");
            return;
        }
        auto ctx = test::open_validated_context();
        const auto c = coverage_of(*ctx, "teapot.obj", render::Footprint::gaussian);
        CHECK(c.boundary.hole_ratio < 0.005);  // the hole goal; measured 0.008 %
        // Vertices alone miss the project's hole goal (0.5 %); boundary particles meet it.
        CHECK(c.vertices.hole_ratio > 4.0 * c.boundary.hole_ratio + 0.005);
        const auto d = coverage_of(*ctx, "teapot.obj", render::Footprint::paper);
        CHECK(d.boundary.hole_ratio < 0.005);  // the hole goal; measured 0
        test::require_no_validation_messages(*ctx);
    }

    TEST_CASE("a surface stretched past its samples stays closed: its splats grow until the density control refills it") {
        // A balloon inflated by 1.35 at once, seen close (splats about ten pixels wide), on the
        // frame the stretch appears: the density control waits for it to settle before adding
        // samples, so the set has spread 1.35 times as far. Drawn as the scenes draw it.
        auto made = sim::make_soft_body(mesh::icosphere(3, 1.0f), {});
        REQUIRE(made.ok());
        sim::SoftBody body = std::move(made).value();
        const mesh::TriangleMesh rest{body.rest_positions, body.triangles, {}, {}, {}};
        const float h = surface::spacing(rest, 0.5f);
        surface::BoundaryParticles samples = surface::sample_surface(rest, {h, 5});
        surface::DensityControl density(body.rest_positions, body.triangles, {});
        for (size_t i = 0; i < body.particle_count(); ++i) body.particles.x[i] = Vec4f(1.35f * body.rest_positions[i].x(), 1.35f * body.rest_positions[i].y(), 1.35f * body.rest_positions[i].z(), 0.0f);
        surface::update_boundary_particles(body.triangles, body.particles.x, body.normals, samples);
        const surface::DensityStats stats = density.update(body.particles.x, body.normals, body.triangles, true, h, 3, samples);
        REQUIRE(stats.inserted == 0);
        splat::Appearance look;
        look.scale = 0.7f * h;
        look.albedo = Vec3f(0.8f, 0.4f, 0.3f);
        render::FrameInputs frame;
        frame.style.footprint = render::Footprint::gaussian;
        frame.style.blend = render::Blend::normalised;
        frame.style.kappa = 2.0f;
        frame.style.surfel_thickness = 0.1f;
        frame.camera.target = Vec3f::Zero();
        frame.camera.eye = Vec3f(0.0f, 0.3f, 2.9f);
        const std::vector<std::array<uint32_t, 3>> tris(body.triangles.begin(), body.triangles.end());
        std::vector<splat::GaussianRecord> grown, kept;
        splat::map_body(body.particles.x, body.normals, {}, body.triangles, &samples, look, nullptr, nullptr, grown);
        surface::BoundaryParticles unscaled = samples;
        unscaled.triangle_growth.clear();
        splat::map_body(body.particles.x, body.normals, {}, body.triangles, &unscaled, look, nullptr, nullptr, kept);
        auto ctx = test::open_validated_context();
        auto g = passes::measure_coverage(*ctx, body.particles.x, tris, grown, frame, 320, 320, look.albedo);
        auto k = passes::measure_coverage(*ctx, body.particles.x, tris, kept, frame, 320, 320, look.albedo);
        REQUIRE_MESSAGE(g.ok(), test::why(g));
        REQUIRE_MESSAGE(k.ok(), test::why(k));
        MESSAGE("thin coverage: grown " << g->thin_ratio * 100.0 << " %, kept at their size " << k->thin_ratio * 100.0 << " %; holes "
                << g->hole_ratio * 100.0 << " / " << k->hole_ratio * 100.0 << " %");
        CHECK(k->thin_ratio > 0.01);   // the dark worms between the samples: measured 1.88 %
        CHECK(g->thin_ratio < 0.005);  // measured 0.24 % (grown only past the refill threshold)
        CHECK(g->thin_ratio < 0.25 * k->thin_ratio);  // measured an eighth
        CHECK(g->hole_ratio <= k->hole_ratio);
        test::require_no_validation_messages(*ctx);
    }

    TEST_CASE("normalised blending averages the front splats: no disc's rim, no gaps, any order") {
        // The paper's disc shows each disc's own shade up to its hard rim: where neighbouring
        // discs' normal fields disagree, a circle. Averaged with their Gaussian weights the
        // shade runs on across them, and the sums do not depend on the order they are drawn in.
        const LumpySphere s;
        const std::vector<splat::GaussianRecord> records = s.records(true);
        // Surfels, as the shipped scenes draw them, large enough on screen for a rim to span pixels.
        render::FrameInputs paper = s.frame;
        paper.style.surfel_thickness = 0.1f;
        render::FrameInputs normalised = paper;
        normalised.style.footprint = render::Footprint::gaussian;
        normalised.style.blend = render::Blend::normalised;
        auto ctx = test::open_validated_context();
        auto disc = s.draw(*ctx, records, paper, 512);
        auto blended = s.draw(*ctx, records, normalised, 512);
        const std::vector<splat::GaussianRecord> reversed(records.rbegin(), records.rend());
        auto blended_reversed = s.draw(*ctx, reversed, normalised, 512);
        REQUIRE_MESSAGE(disc.ok(), test::why(disc));
        REQUIRE_MESSAGE(blended.ok(), test::why(blended));
        REQUIRE_MESSAGE(blended_reversed.ok(), test::why(blended_reversed));
        MESSAGE("shading error against the lit mesh: paper disc " << disc->shading_error << ", normalised " << blended->shading_error
                << "; holes " << disc->hole_ratio * 100.0 << " % / " << blended->hole_ratio * 100.0 << " %; specks "
                << disc->speck_ratio * 100.0 << " % / " << blended->speck_ratio * 100.0 << " %; IoU " << disc->silhouette_iou << " / "
                << blended->silhouette_iou);
        CHECK(blended->shading_error < 0.8 * disc->shading_error);  // measured 0.0053 against 0.0092
        CHECK(blended->hole_ratio < 0.001);  // measured 0
        // Its silhouette fades over a pixel or two where the disc's is hard: a few edge pixels
        // darker than half the mesh's, within the project's speck goal; the outline a little wider.
        CHECK(blended->speck_ratio < 0.002);
        CHECK(blended->silhouette_iou > 0.93);  // measured 0.953
        // Float sums in another order differ in their last bits, not by a visible step.
        int worst = 0;
        for (size_t i = 0; i < blended->splats.pixels.size(); ++i)
            worst = std::max(worst, std::abs(int(blended->splats.pixels[i]) - int(blended_reversed->splats.pixels[i])));
        CHECK(worst <= 1);
        test::require_no_validation_messages(*ctx);
    }

    TEST_CASE("small splats drawn fewer and larger by their thinning order: the surface stays closed and lit") {
        // The lumpy sphere's boundary particles alone (as over a model's embedded surface), about
        // 1.6 pixels wide at this size: thinned below 4 pixels, about a sixth of them are drawn,
        // each 2.5 times as wide. In their order the kept ones cover the surface evenly; the same
        // levels shuffled (a random subset of each size) leave gaps once few are kept.
        LumpySphere s;
        const mesh::TriangleMesh rest{s.body.rest_positions, s.body.triangles, {}, {}, {}};
        const float h = surface::spacing(rest, 0.5f);
        const auto records = [&s] {
            std::vector<splat::GaussianRecord> out;
            splat::map_body({}, {}, {}, s.body.triangles, &s.samples, s.look, nullptr, &s.field, out);
            return out;
        };
        surface::place_in_thin_order(s.samples.position, s.samples.normal, {}, h, s.samples.thin_level);
        const std::vector<splat::GaussianRecord> ordered = records();
        std::shuffle(s.samples.thin_level.begin(), s.samples.thin_level.end(), std::mt19937(5));
        const std::vector<splat::GaussianRecord> shuffled = records();
        render::FrameInputs all = s.frame;
        all.style.surfel_thickness = 0.1f;
        all.style.footprint = render::Footprint::gaussian;
        all.style.blend = render::Blend::normalised;
        all.style.kappa = 2.0f;
        render::FrameInputs thinned = all, heavily = all;
        thinned.style.thin_below = 4.0f;
        heavily.style.thin_below = 8.0f;
        auto ctx = test::open_validated_context();
        auto a = s.draw(*ctx, ordered, all, 160);
        auto t = s.draw(*ctx, ordered, thinned, 160);
        auto th = s.draw(*ctx, ordered, heavily, 160);
        auto uh = s.draw(*ctx, shuffled, heavily, 160);
        REQUIRE_MESSAGE(a.ok(), test::why(a));
        REQUIRE_MESSAGE(t.ok(), test::why(t));
        REQUIRE_MESSAGE(th.ok(), test::why(th));
        REQUIRE_MESSAGE(uh.ok(), test::why(uh));
        MESSAGE("all / thinned below 4 px / below 8 px in order / below 8 px shuffled: holes " << a->hole_ratio * 100.0 << " / "
                << t->hole_ratio * 100.0 << " / " << th->hole_ratio * 100.0 << " / " << uh->hole_ratio * 100.0 << " %; specks "
                << a->speck_ratio * 100.0 << " / " << t->speck_ratio * 100.0 << " / " << th->speck_ratio * 100.0 << " / "
                << uh->speck_ratio * 100.0 << " %; shading error " << a->shading_error << " / " << t->shading_error << " / "
                << th->shading_error << " / " << uh->shading_error << "; IoU " << a->silhouette_iou << " / " << t->silhouette_iou);
        // Below 4 pixels: as closed and as lit as all of them drawn.
        CHECK(t->hole_ratio <= a->hole_ratio + 0.0005);
        CHECK(t->speck_ratio <= a->speck_ratio + 0.0005);
        CHECK(t->shading_error < 1.25 * a->shading_error + 0.005);  // measured 0.0064 against 0.0062
        CHECK(std::abs(t->silhouette_iou - a->silhouette_iou) < 0.03);  // measured 0.956 against 0.962
        int differ = 0;
        for (size_t i = 0; i < a->splats.pixels.size(); ++i) differ += std::abs(int(a->splats.pixels[i]) - int(t->splats.pixels[i])) > 2;
        CHECK(differ > 0);  // and something was thinned
        // Below 8 pixels (an eighth drawn, the most): still closed in order; the same levels shuffled
        // leave holes and dark specks where the kept ones happen to lie apart.
        CHECK(th->hole_ratio < 0.001);
        CHECK(th->speck_ratio < 0.002);  // measured 0
        CHECK(uh->hole_ratio + uh->speck_ratio > 4.0 * (th->hole_ratio + th->speck_ratio) + 0.002);  // measured 0
        CHECK(uh->shading_error > 1.3 * th->shading_error);  // measured 0.016 against 0.012
        test::require_no_validation_messages(*ctx);
    }

    TEST_CASE("splats whose normal turns across them are lit closer to the mesh than flat ones") {
        // Lit with one normal each, the lumpy sphere's discs show as facets; with the surface's
        // turn across each, the shading runs on across them.
        const LumpySphere s;
        const std::vector<splat::GaussianRecord> flat = s.records(false), turning = s.records(true);
        auto ctx = test::open_validated_context();
        auto a = s.draw(*ctx, flat, s.frame);
        auto b = s.draw(*ctx, turning, s.frame);
        REQUIRE_MESSAGE(a.ok(), test::why(a));
        REQUIRE_MESSAGE(b.ok(), test::why(b));
        MESSAGE("shading error against the lit mesh: flat " << a->shading_error << ", turning " << b->shading_error);
        CHECK(b->shading_error < 0.5 * a->shading_error);  // measured 0.014 against 0.040
        // The footprint is the same: only the light changed.
        CHECK(b->hole_ratio == a->hole_ratio);
        CHECK(b->silhouette_iou == a->silhouette_iou);
        test::require_no_validation_messages(*ctx);
    }
}

TEST_SUITE("render/coverage") {
    TEST_CASE("a model's own colours: the lit mesh is drawn in them, and the colour error sees a wrong one") {
        auto ctx = test::open_validated_context();
        const LumpySphere s;
        // Green above the equator, blue below, on the particles; the samples interpolate them.
        std::vector<Vec3f> colors(s.body.particle_count());
        for (size_t i = 0; i < colors.size(); ++i) colors[i] = s.body.rest_positions[i].y() > 0.0f ? Vec3f(0.1f, 0.7f, 0.2f) : Vec3f(0.1f, 0.2f, 0.8f);
        std::vector<splat::GaussianRecord> records;
        splat::map_body(s.body.particles.x, s.body.normals, colors, s.body.triangles, &s.samples, s.look, nullptr, &s.field, records);
        auto same = passes::measure_coverage(*ctx, s.body.particles.x, s.triangles, records, s.frame, 256, 256, s.albedo, {}, colors);
        REQUIRE(same.ok());
        // Drawn in the material's albedo instead, the mesh disagrees with the coloured splats.
        auto plain = passes::measure_coverage(*ctx, s.body.particles.x, s.triangles, records, s.frame, 256, 256, s.albedo);
        REQUIRE(plain.ok());
        MESSAGE("colour error against the coloured mesh " << same->color_error << ", against the plain one " << plain->color_error);
        CHECK(same->color_error < 0.04);  // 0.023 measured: the splats blur the equator over a spacing
        CHECK(plain->color_error > 4.0 * same->color_error);  // measured 0.32 against 0.023
        // The lit mesh is green where it is green: no red of the albedo in its upper half.
        size_t green = 0, red = 0;
        for (uint32_t y = 0; y < 100; ++y)
            for (uint32_t x = 0; x < 256; ++x) {
                const uint8_t* p = same->shaded.at(x, y);
                if (p[3] < 128) continue;
                green += p[1] > p[0] ? 1 : 0;
                red += p[0] > p[1] ? 1 : 0;
            }
        CHECK(green > 1000);
        CHECK(red == 0);
        test::require_no_validation_messages(*ctx);
    }

    TEST_CASE("a textured look: the lit mesh samples the texture at each pixel, and the colour error sees it moved") {
        auto ctx = test::open_validated_context();
        const LumpySphere s;
        // Two texels, green then blue, clamped, with u rising with height: the lower half
        // green, the upper blue, a blend over the middle of the body.
        const std::vector<uint8_t> texels = {40, 180, 60, 255, 30, 60, 200, 255};
        const Vec3f green = asset::srgb_to_linear(Vec3f(40, 180, 60) / 255.0f), blue = asset::srgb_to_linear(Vec3f(30, 60, 200) / 255.0f);
        const std::vector<render::MeshTexture> textures{{2, 1, texels, VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE, VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE}};
        const auto u_of = [&](uint32_t v, float sign) { return 0.5f + 0.5f * sign * s.body.rest_positions[v].y(); };
        // The texture read on the CPU as a GPU reads it: texel centres at u = 1/4 and 3/4.
        const auto color_at = [&](float u) { return Vec3f(green + std::clamp((u - 0.25f) / 0.5f, 0.0f, 1.0f) * (blue - green)); };
        const size_t n = s.triangles.size();
        std::vector<int32_t> texture(n, 0);
        std::vector<std::array<Vec2f, 3>> up(n), down(n);
        std::vector<std::array<Vec3f, 3>> tint(n, {Vec3f::Ones(), Vec3f::Ones(), Vec3f::Ones()});
        for (size_t t = 0; t < n; ++t)
            for (int k = 0; k < 3; ++k) up[t][k] = Vec2f(u_of(s.triangles[t][k], 1.0f), 0.5f), down[t][k] = Vec2f(u_of(s.triangles[t][k], -1.0f), 0.5f);
        const passes::ReferenceTextures textured{texture, up, tint, textures}, flipped{texture, down, tint, textures};
        // The splats painted from the texture where their particles stand.
        std::vector<Vec3f> colors(s.body.particle_count());
        for (uint32_t i = 0; i < colors.size(); ++i) colors[i] = color_at(u_of(i, 1.0f));
        std::vector<splat::GaussianRecord> records;
        splat::map_body(s.body.particles.x, s.body.normals, colors, s.body.triangles, &s.samples, s.look, nullptr, &s.field, records);
        auto right = passes::measure_coverage(*ctx, s.body.particles.x, s.triangles, records, s.frame, 256, 256, s.albedo, {}, {}, &textured);
        auto wrong = passes::measure_coverage(*ctx, s.body.particles.x, s.triangles, records, s.frame, 256, 256, s.albedo, {}, {}, &flipped);
        REQUIRE_MESSAGE(right.ok(), test::why(right));
        REQUIRE_MESSAGE(wrong.ok(), test::why(wrong));
        MESSAGE("colour error against the texture " << right->color_error << ", against it upside down " << wrong->color_error);
        CHECK(right->color_error < 0.03);  // measured 0.014
        CHECK(wrong->color_error > 4.0 * right->color_error);  // measured 0.19 against 0.014
        // Green below, blue above, in the lit mesh as drawn from the texture; the other way round
        // with the coordinates flipped.
        const auto mean_row = [](const core::ImageRgba8& image, bool want_green) {
            double rows = 0.0;
            size_t count = 0;
            for (uint32_t y = 0; y < image.height; ++y)
                for (uint32_t x = 0; x < image.width; ++x) {
                    const uint8_t* p = image.at(x, y);
                    if (p[3] < 255 || (p[1] > 2 * p[2]) != want_green || (p[2] > 2 * p[1]) == want_green) continue;
                    rows += y, ++count;
                }
            CHECK(count > 1000);
            return count ? rows / double(count) : 0.0;
        };
        CHECK(mean_row(right->shaded, true) > mean_row(right->shaded, false) + 40.0);
        CHECK(mean_row(wrong->shaded, true) + 40.0 < mean_row(wrong->shaded, false));
        test::require_no_validation_messages(*ctx);
    }

    TEST_CASE("a texture of one texel draws as the same colour given at the vertices, away from the silhouette") {
        auto ctx = test::open_validated_context();
        const LumpySphere s;
        const std::vector<uint8_t> texel = {200, 120, 40, 255};
        const Vec3f linear = asset::srgb_to_linear(Vec3f(200, 120, 40) / 255.0f);
        const Vec3f tint(0.9f, 1.0f, 0.8f);
        const std::vector<render::MeshTexture> textures{{1, 1, texel, VK_SAMPLER_ADDRESS_MODE_REPEAT, VK_SAMPLER_ADDRESS_MODE_REPEAT}};
        const size_t n = s.triangles.size();
        const std::vector<int32_t> texture(n, 0);
        const std::vector<std::array<Vec2f, 3>> uv(n, {Vec2f(0.1f, 0.2f), Vec2f(0.7f, 0.3f), Vec2f(0.4f, 0.9f)});
        const std::vector<std::array<Vec3f, 3>> tints(n, {tint, tint, tint});
        const passes::ReferenceTextures textured{texture, uv, tints, textures};
        const std::vector<Vec3f> colors(s.body.particle_count(), Vec3f(linear.cwiseProduct(tint)));
        const std::vector<splat::GaussianRecord> records = s.records(true);
        auto a = passes::measure_coverage(*ctx, s.body.particles.x, s.triangles, records, s.frame, 256, 256, s.albedo, {}, {}, &textured);
        auto b = passes::measure_coverage(*ctx, s.body.particles.x, s.triangles, records, s.frame, 256, 256, s.albedo, {}, colors);
        REQUIRE_MESSAGE(a.ok(), test::why(a));
        REQUIRE_MESSAGE(b.ok(), test::why(b));
        const core::ImageRgba8& mask = b->mesh;
        const auto inside = [&](uint32_t x, uint32_t y) {
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx)
                    if (mask.at(uint32_t(int(x) + dx), uint32_t(int(y) + dy))[3] < 128) return false;
            return true;
        };
        size_t compared = 0;
        int worst = 0;
        for (uint32_t y = 1; y + 1 < 256; ++y)
            for (uint32_t x = 1; x + 1 < 256; ++x) {
                if (!inside(x, y)) continue;
                ++compared;
                for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(int(a->shaded.at(x, y)[k]) - int(b->shaded.at(x, y)[k])));
            }
        MESSAGE(compared << " pixels compared, largest difference " << worst << " of 255");
        CHECK(compared > 10000);
        CHECK(worst <= 3);  // the supersampled image rounds its means; the texel is decoded in 8 bits
        test::require_no_validation_messages(*ctx);
    }

    TEST_CASE("textured splats read their textures under each pixel: checkers' edges drawn sharp, alike on every path") {
        auto ctx = test::open_validated_context();
        const LumpySphere s;
        // Two 8 x 8 checkers (squares of 8 x 8 texels: sharp edges under a bilinear read),
        // clamped, projected onto the body from the front: orange and teal on the triangles below
        // y = 0.3, violet and yellow above (the second texture of two).
        const auto make_checker = [](const Vec3f& light, const Vec3f& dark) {
            asset::Texture t;
            t.width = t.height = 64;
            t.wrap_u = t.wrap_v = asset::Wrap::clamp;
            for (uint32_t y = 0; y < 64; ++y)
                for (uint32_t x = 0; x < 64; ++x) {
                    const Vec3f& c = ((x / 8 + y / 8) & 1u) != 0 ? light : dark;
                    const uint8_t texel[4] = {uint8_t(c.x()), uint8_t(c.y()), uint8_t(c.z()), 255};
                    t.rgba.insert(t.rgba.end(), texel, texel + 4);
                }
            return t;
        };
        const asset::Texture checkers[2] = {make_checker({230, 140, 30}, {20, 150, 160}), make_checker({120, 40, 200}, {240, 230, 60})};
        std::vector<render::MeshTexture> textures;
        for (const asset::Texture& t : checkers)
            textures.push_back({64, 64, t.rgba, VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE, VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE});
        const auto uv_of = [](const Vec3f& p) { return Vec2f(0.5f + 0.4f * p.x(), 0.5f - 0.4f * p.y()); };
        const size_t n = s.triangles.size();
        std::vector<int32_t> texture(n, 0);
        std::vector<std::array<Vec2f, 3>> uv(n);
        const std::vector<std::array<Vec3f, 3>> tint(n, {Vec3f::Ones(), Vec3f::Ones(), Vec3f::Ones()});
        for (size_t t = 0; t < n; ++t) {
            Vec3f centre = Vec3f::Zero();
            for (int k = 0; k < 3; ++k) {
                const Vec3f& p = s.body.rest_positions[s.triangles[t][size_t(k)]];
                uv[t][size_t(k)] = uv_of(p);
                centre += p / 3.0f;
            }
            texture[t] = centre.y() > 0.3f ? 1 : 0;
        }
        const passes::ReferenceTextures reference{texture, uv, tint, textures};
        // Each sample painted with the texel under its centre (what a splat of one colour draws)
        // and given where the texture lies on it: the projection's gradient in its tangent plane.
        surface::BoundaryParticles samples = s.samples;
        samples.color.resize(samples.size());
        samples.texcoord.resize(samples.size());
        for (size_t k = 0; k < samples.size(); ++k) {
            const Vec3f& p = samples.position[k];
            const Mat3f plane = Mat3f::Identity() - samples.normal[k] * samples.normal[k].transpose();
            const int32_t which = texture[samples.triangle[k]];
            samples.color[k] = scene::pack_color(checkers[which].sample(uv_of(p)));
            samples.texcoord[k] = {uv_of(p), plane * Vec3f(0.4f, 0, 0), plane * Vec3f(0, -0.4f, 0), Vec3f::Ones(), which, 1.0f};
        }
        // The samples alone are splats, as on a model whose fine surface rides a coarse body.
        std::vector<splat::GaussianRecord> records;
        splat::map_body({}, {}, {}, s.body.triangles, &samples, s.look, nullptr, &s.field, records);
        std::vector<splat::GaussianTexcoord> texcoords;
        splat::TexcoordScratch scratch;
        splat::map_texcoords(s.body.rest_positions, s.body.particles.x, s.body.triangles, 0, {}, samples, records.size(), texcoords, scratch);
        render::FrameInputs frame = s.frame;
        frame.style.footprint = render::Footprint::gaussian;
        frame.style.blend = render::Blend::normalised;
        const passes::SplatTexturing texturing{texcoords, textures};
        auto sharp = passes::measure_coverage(*ctx, s.body.particles.x, s.triangles, records, frame, 256, 256, s.albedo, {}, {}, &reference, &texturing);
        auto flat = passes::measure_coverage(*ctx, s.body.particles.x, s.triangles, records, frame, 256, 256, s.albedo, {}, {}, &reference);
        REQUIRE_MESSAGE(sharp.ok(), test::why(sharp));
        REQUIRE_MESSAGE(flat.ok(), test::why(flat));
        MESSAGE("colour error against the textured mesh: " << sharp->color_error << " reading the texture per pixel, " << flat->color_error
                                                           << " one colour a splat");
        // 2026-11-29, Lavapipe: 0.0203 against 0.0751 (most of the first is the soft rim and the
        // band where the two textures' splats meet).
        CHECK(sharp->color_error < 0.026);
        CHECK(sharp->color_error < 0.4 * flat->color_error);  // measured 0.020 against 0.075
        CHECK(sharp->hole_ratio == flat->hole_ratio);

        // One textured frame drawn by a renderer of its own.
        const auto draw = [&](render::RendererOptions o, std::span<const splat::GaussianRecord> drawn,
                              std::span<const splat::GaussianTexcoord> entries, const render::FrameInputs& f) {
            o.width = o.height = 256;
            o.max_splats = uint32_t(drawn.size());
            o.frames_in_flight = 1;
            o.textures = 2;
            auto r = passes::OffscreenRenderer::create(*ctx, o);
            REQUIRE_MESSAGE(r.ok(), test::why(r));
            REQUIRE(r.value()->set_textures(textures).ok());
            r.value()->set_texcoords(entries);
            REQUIRE(r.value()->render(drawn, f).ok());
            auto image = r.value()->finish();
            REQUIRE(image.ok());
            return std::move(image).value();
        };

        // Every splat path the device has draws the same texture.
        std::optional<core::ImageRgba8> first;
        for (const render::SplatPath path : {render::SplatPath::geometry, render::SplatPath::mesh, render::SplatPath::vertex}) {
            if (const std::string why = render::splat_path_unsupported(ctx->caps(), path); !why.empty()) {
                test::skip("path " + std::string(render::splat_path_name(path)) + ": " + why);
                continue;
            }
            render::RendererOptions o;
            o.normalised = true;
            o.path = path;
            core::ImageRgba8 image = draw(o, records, texcoords, frame);
            if (!first) {
                first = std::move(image);
                continue;
            }
            auto diff = core::compare_images(*first, image, 3);
            REQUIRE(diff.ok());
            MESSAGE(std::string(render::splat_path_name(path)) << " against the first path: " << diff->share_over * 100.0 << " % of pixels over 3/255");
            CHECK(diff->share_over < 0.005);  // measured 0 on every path
        }

        // Sorted on the GPU, each record finds its texture entry through the sort's order: the
        // same image as the records and entries sorted together on the CPU.
        const auto sorted = [&](render::SplatOrder order) {
            render::RendererOptions o;
            o.gpu_sort = order == render::SplatOrder::gpu;
            render::FrameInputs over = frame;
            over.style.blend = render::Blend::over;
            over.style.order = order;
            std::vector<splat::GaussianRecord> drawn = records;
            std::vector<splat::GaussianTexcoord> entries = texcoords;
            if (order == render::SplatOrder::cpu) {
                splat::SortScratch sort;
                splat::sort_far_to_near(drawn, math::look_at(over.camera.eye, over.camera.target, over.camera.up), sort);
                splat::reorder_like_last_sort(sort, entries);
            }
            return draw(o, drawn, entries, over);
        };
        auto diff = core::compare_images(sorted(render::SplatOrder::cpu), sorted(render::SplatOrder::gpu), 1);
        REQUIRE(diff.ok());
        MESSAGE("textured, GPU against CPU sort: " << diff->share_over * 100.0 << " % of pixels over 1/255");
        CHECK(diff->share_over == 0.0);
        test::require_no_validation_messages(*ctx);
    }
}
