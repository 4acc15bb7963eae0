#include <doctest/doctest.h>

#include <cmath>
#include <optional>

#include "core/image.h"
#include "gpu/pipeline_counter.h"
#include "passes/coverage.h"
#include "passes/offscreen_renderer.h"
#include "splat/gaussian_record.h"
#include "support/gpu_fixture.h"
#include "support/skip.h"
#include "support/why.h"

using namespace pbdsplat;

namespace {

// Two square plates facing the camera: a near one (red splats) over the left half of a far one
// (blue splats). The near plate's splats reach past its right edge by their radius, over the far
// plate: the band a user sees as the near surface's colour bleeding over an occluding contour.
struct Plates {
    std::vector<Vec4f> x;
    std::vector<std::array<uint32_t, 3>> triangles;
    std::vector<splat::GaussianRecord> records;
    render::FrameInputs frame;
    static constexpr uint32_t k_size = 256;

    void plate(float x0, float x1, float y0, float y1, float z, const Vec3f& albedo, float h) {
        const auto v = uint32_t(x.size());
        x.push_back({x0, y0, z, 1.0f}), x.push_back({x1, y0, z, 1.0f}), x.push_back({x1, y1, z, 1.0f}), x.push_back({x0, y1, z, 1.0f});
        triangles.push_back({v, v + 1, v + 2}), triangles.push_back({v, v + 2, v + 3});
        splat::Appearance look;
        look.albedo = albedo;
        look.scale = 0.7f * h;
        // Samples at spacing h, half a spacing in from each edge (as a maximal sampling leaves them).
        for (float px = x0 + 0.5f * h; px < x1; px += h)
            for (float py = y0 + 0.5f * h; py < y1; py += h) records.push_back(splat::make_record({px, py, z}, {0, 0, 1}, look));
    }

    Plates() {
        const float h = 0.05f;
        plate(-1.0f, 0.0f, -0.6f, 0.6f, 0.5f, {0.9f, 0.05f, 0.05f}, h);
        plate(-1.2f, 1.2f, -0.8f, 0.8f, 0.0f, {0.05f, 0.05f, 0.9f}, h);
        frame.camera.eye = {0.0f, 0.0f, 4.0f};
        frame.camera.target = {0.0f, 0.0f, 0.0f};
        frame.style.footprint = render::Footprint::gaussian;
        frame.style.blend = render::Blend::normalised;
        frame.style.kappa = 2.0f;
        frame.style.surfel_thickness = 0.1f;
        frame.lighting.environment.sampling = render::EnvSampling::off;
        frame.lighting.direction = {0.0f, 0.0f, 1.0f};
        frame.style.occluder_tolerance = 3.0f * 0.7f * h;
        frame.style.occluder_push = 4.0f * 0.7f * h;
    }

    // Pixel column of the near plate's right edge (x = 0 at z = 0.5, seen from the eye on the axis).
    static int edge_column() { return int(k_size) / 2; }
};

struct BandCount {
    int red = 0, blue = 0, holes = 0;
};

// Pixels along the rows through the plates' middle, `from` to `to` columns right of the near
// plate's edge.
BandCount count_band(const core::ImageRgba8& image, int from, int to) {
    BandCount c;
    for (int y = int(Plates::k_size) / 2 - 30; y < int(Plates::k_size) / 2 + 30; ++y)
        for (int x = Plates::edge_column() + from; x <= Plates::edge_column() + to; ++x) {
            const uint8_t* p = &image.pixels[(size_t(y) * image.width + size_t(x)) * 4];
            if (p[3] < 128) ++c.holes;
            else if (p[0] > p[2]) ++c.red;
            else ++c.blue;
        }
    return c;
}

// The plates drawn once on `path` through a renderer with normalised blending and occluders.
std::unique_ptr<passes::OffscreenRenderer> plates_frame(gpu::Context& ctx, const Plates& s, const render::FrameInputs& frame,
                                                        render::SplatPath path) {
    render::RendererOptions ro;
    ro.width = ro.height = Plates::k_size;
    ro.max_splats = uint32_t(s.records.size());
    ro.frames_in_flight = 1;
    ro.normalised = ro.occluders = true;
    ro.path = path;
    auto r = passes::OffscreenRenderer::create(ctx, ro);
    REQUIRE_MESSAGE(r.ok(), test::why(r));
    r.value()->set_occluders(s.x, s.triangles);
    REQUIRE(r.value()->render(s.records, frame).ok());
    return std::move(r).value();
}

} // namespace

TEST_SUITE("render/occluder_pass") {
    TEST_CASE("mesh occluders end a splat at an occluding contour, without opening holes") {
        const Plates s;
        auto ctx = test::open_validated_context();
        render::FrameInputs cores = s.frame;  // the splats' own opaque cores hide what is behind
        render::FrameInputs mesh = s.frame;
        mesh.style.mesh_occluders = true;
        auto a = passes::measure_coverage(*ctx, s.x, s.triangles, s.records, cores, Plates::k_size, Plates::k_size);
        auto b = passes::measure_coverage(*ctx, s.x, s.triangles, s.records, mesh, Plates::k_size, Plates::k_size);
        REQUIRE_MESSAGE(a.ok(), test::why(a));
        REQUIRE_MESSAGE(b.ok(), test::why(b));
        // Just right of the edge the far plate shows; the near plate's splats reach 2 standard
        // deviations (0.07 world units, about 4 pixels here) past it.
        const BandCount over_cores = count_band(a->splats, 1, 3), over_mesh = count_band(b->splats, 1, 3);
        MESSAGE("three columns right of the near plate's edge: splat cores " << over_cores.red << " red / " << over_cores.blue
                << " blue, mesh occluders " << over_mesh.red << " red / " << over_mesh.blue << " blue");
        CHECK(over_cores.red > 40);  // the bleed the occluders remove (the test can fail)
        CHECK(over_mesh.red == 0);
        CHECK(over_mesh.holes == 0);
        // Left of the edge, the near plate still shows to its edge.
        const BandCount inside = count_band(b->splats, -3, -1);
        CHECK(inside.blue == 0);
        CHECK(inside.holes == 0);
        CHECK(b->hole_ratio < 0.001);  // a fifth of the hole goal (0.5 %)
        // Past the outline (no surface behind) a splat keeps one pixel of its rim, no more: the
        // silhouette follows the surface's closer than the splats' own reach does.
        MESSAGE("silhouette IoU: splat cores " << a->silhouette_iou << ", mesh occluders " << b->silhouette_iou);
        CHECK(b->silhouette_iou > a->silhouette_iou);
        // The far plate's right edge (x = 1.2 at z = 0, 45-degree field of view).
        const double half_width = 4.0 * std::tan(0.5 * 45.0 * 3.14159265358979 / 180.0);
        const int outline = int(std::lround((1.2 / half_width + 1.0) * 0.5 * Plates::k_size));
        const size_t row = Plates::k_size / 2;
        auto alpha_at = [&](const core::ImageRgba8& image, int x) { return image.pixels[(row * Plates::k_size + size_t(x)) * 4 + 3]; };
        CHECK(alpha_at(a->splats, outline + 2) > 0);  // the splats' own reach runs on past it
        for (int x = outline + 2; x < int(Plates::k_size); ++x) CHECK(alpha_at(b->splats, x) == 0);
        test::require_no_validation_messages(*ctx);
    }

    TEST_CASE("one-sided occluders: a solid's front faces draw as both sides do; faces wound away hide nothing") {
        // The near plate's two triangles first, drawn front faces only (as a solid's surface is).
        Plates s;
        render::FrameInputs frame = s.frame;
        frame.style.mesh_occluders = true;
        auto ctx = test::open_validated_context();
        const auto draw = [&](const Plates& p, size_t one_sided) {
            auto c = passes::measure_coverage(*ctx, p.x, p.triangles, p.records, frame, Plates::k_size, Plates::k_size, std::nullopt, {}, {},
                                              nullptr, nullptr, one_sided);
            REQUIRE_MESSAGE(c.ok(), test::why(c));
            return std::move(c).value();
        };
        const passes::Coverage both = draw(s, 0), front = draw(s, 2);
        auto diff = core::compare_images(front.splats, both.splats, 0);
        REQUIRE(diff.ok());
        CHECK(diff->share_over == 0.0);  // the plate faces the eye: the same pixels
        // Wound the other way, the near plate is culled: its splats, half a unit in front of the
        // surface the occluders then show (the far plate), are cut, and the far plate shows.
        Plates turned = s;
        for (size_t k = 0; k < 2; ++k) std::swap(turned.triangles[k][1], turned.triangles[k][2]);
        const BandCount inside_both = count_band(both.splats, -60, -10), inside_turned = count_band(draw(turned, 2).splats, -60, -10);
        MESSAGE("inside the near plate: both sides " << inside_both.red << " red, turned away " << inside_turned.red << " red / "
                                                     << inside_turned.blue << " blue");
        CHECK(inside_both.red > 1000);  // 60 rows x 51 columns, all red
        CHECK(inside_turned.red == 0);
        CHECK(inside_turned.blue > 1000);
        test::require_no_validation_messages(*ctx);
    }

    TEST_CASE("mesh occluders draw the same on every splat path") {
        // Each path computes its carrier corners' depths on the surfel's plane in its own stage
        // (geometry, mesh, vertex); the accumulation compares them with the mesh's.
        const Plates s;
        render::FrameInputs frame = s.frame;
        frame.style.mesh_occluders = true;
        auto ctx = test::open_validated_context();
        std::optional<core::ImageRgba8> first;
        for (render::SplatPath path : {render::SplatPath::geometry, render::SplatPath::mesh, render::SplatPath::vertex}) {
            if (const std::string why = render::splat_path_unsupported(ctx->caps(), path); !why.empty()) {
                test::skip("the " + std::string(render::splat_path_name(path)) + " path: " + why);
                continue;
            }
            auto r = plates_frame(*ctx, s, frame, path);
            auto image = r->finish();
            REQUIRE_MESSAGE(image.ok(), test::why(image));
            const BandCount band = count_band(image.value(), 1, 3);
            MESSAGE(std::string(render::splat_path_name(path)) << ": three columns right of the near plate's edge " << band.red
                                                                 << " red / " << band.blue << " blue / " << band.holes << " open");
            CHECK(band.red == 0);
            CHECK(band.holes == 0);
            if (!first) {
                first = std::move(image).value();
                continue;
            }
            auto diff = core::compare_images(image.value(), *first, 2);
            REQUIRE(diff.ok());
            CHECK(diff->share_over < 0.002);  // measured 0 % (the paths draw alike)
        }
        test::require_no_validation_messages(*ctx);
    }

    TEST_CASE("a splat the mesh occluders hide whole is dropped before rasterisation where the front stage can drop it") {
        // The near plate hides about a fifth of the splats (of its own 480 and the far plate's
        // 1,536): the geometry stage emits no carrier for those; vertex pulling keeps every one,
        // and the rasteriser covers its pixels before the depth test throws them away (Lavapipe
        // rejects them before the fragment shader, so the fragment counts agree; the time the
        // rasteriser spends does not: docs/BENCHMARKS.md, "Mesh occluders").
        const Plates s;
        auto ctx = test::open_validated_context();
        if (!ctx->caps().pipeline_statistics) {
            test::skip("device '" + ctx->caps().name + "' has no pipeline-statistics queries: the splat work is not counted");
            return;
        }
        const auto counts = [&](render::SplatPath path) {
            render::FrameInputs frame = s.frame;
            frame.style.mesh_occluders = true;
            auto r = plates_frame(*ctx, s, frame, path);
            auto image = r->finish();
            REQUIRE_MESSAGE(image.ok(), test::why(image));
            return r->timings().splat_counts;
        };
        if (const std::string why = render::splat_path_unsupported(ctx->caps(), render::SplatPath::geometry); !why.empty()) {
            test::skip("the geometry path: " + why);
            return;
        }
        const gpu::PipelineCounts vertex = counts(render::SplatPath::vertex), culled = counts(render::SplatPath::geometry);
        MESSAGE("primitives: geometry stage " << culled.primitives << ", vertex pulling " << vertex.primitives << " (2 a splat); fragments "
                                              << culled.fragments << ", " << vertex.fragments);
        CHECK(vertex.primitives == 2 * s.records.size());  // one draw of every splat
        CHECK(double(culled.primitives) < 0.85 * double(vertex.primitives));  // measured 0.77 (456 splats hidden)
        CHECK(culled.fragments > 0);
        CHECK(double(culled.fragments) <= 1.01 * double(vertex.fragments));  // the same picture (measured 1 fragment apart)
        test::require_no_validation_messages(*ctx);
    }

    TEST_CASE("mesh occluders cut the paper's disc at an occluding contour too") {
        // The disc's one pass writes depth (the nearest disc wins), after the occluders' pass.
        const Plates s;
        render::FrameInputs cores = s.frame;
        cores.style.footprint = render::Footprint::paper;
        cores.style.blend = render::Blend::over;
        cores.style.kappa = 0.0f;  // the closing size
        render::FrameInputs mesh = cores;
        mesh.style.mesh_occluders = true;
        auto ctx = test::open_validated_context();
        auto a = passes::measure_coverage(*ctx, s.x, s.triangles, s.records, cores, Plates::k_size, Plates::k_size);
        auto b = passes::measure_coverage(*ctx, s.x, s.triangles, s.records, mesh, Plates::k_size, Plates::k_size);
        REQUIRE_MESSAGE(a.ok(), test::why(a));
        REQUIRE_MESSAGE(b.ok(), test::why(b));
        const BandCount over_depth = count_band(a->splats, 1, 3), over_mesh = count_band(b->splats, 1, 3);
        MESSAGE("paper disc, three columns right of the near plate's edge: own depth " << over_depth.red << " red / "
                << over_depth.blue << " blue, mesh occluders " << over_mesh.red << " red / " << over_mesh.blue << " blue / "
                << over_mesh.holes << " open");
        CHECK(over_depth.red > 40);
        CHECK(over_mesh.red == 0);
        CHECK(over_mesh.holes == 0);
        CHECK(count_band(b->splats, -3, -1).blue == 0);
        CHECK(b->hole_ratio < 0.001);  // a fifth of the hole goal (0.5 %)
        test::require_no_validation_messages(*ctx);
    }

    TEST_CASE("a splat a little in front of the mesh's surface is kept, behind it dropped: twice the tolerance in front") {
        // One plate's mesh at z = 0 and a layer of splats over it at depth offset dz (the eye
        // looks down -z): how much of the plate the layer covers under mesh occluders.
        const float h = 0.05f, tolerance = 3.0f * 0.7f * h;
        const auto covered = [&](gpu::Context& ctx, float dz) {
            Plates s;
            s.x.clear(), s.triangles.clear(), s.records.clear();
            s.plate(-0.6f, 0.6f, -0.6f, 0.6f, 0.0f, {0.9f, 0.05f, 0.05f}, h);
            for (auto& r : s.records) r.position[2] += dz;
            render::FrameInputs f = s.frame;
            f.style.mesh_occluders = true;
            f.style.occluder_push = 3.0f * tolerance;  // the early depth test keeps all three layers
            auto c = passes::measure_coverage(ctx, s.x, s.triangles, s.records, f, Plates::k_size, Plates::k_size);
            REQUIRE_MESSAGE(c.ok(), test::why(c));
            return 1.0 - c->hole_ratio;
        };
        auto ctx = test::open_validated_context();
        const double front = covered(*ctx, 1.5f * tolerance), behind = covered(*ctx, -1.5f * tolerance),
                     far_front = covered(*ctx, 2.5f * tolerance), on = covered(*ctx, 0.0f);
        MESSAGE("covered: on the surface " << on << ", 1.5 tolerances in front " << front << ", behind " << behind
                << ", 2.5 in front " << far_front);
        CHECK(on > 0.99);  // measured 1
        CHECK(front > 0.99);  // measured 1
        CHECK(behind < 0.01);  // measured 0
        CHECK(far_front < 0.01);  // measured 0
        test::require_no_validation_messages(*ctx);
    }
}
