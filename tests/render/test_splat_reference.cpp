// The GPU splat paths against the plain CPU reference of tests/support/splat_reference.h: a few
// splats, flat lighting, every path and carrier.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdlib>
#include <string>

#include "render/cpu_shading.h"
#include "render/frame_uniforms.h"
#include "render/splat_renderer.h"
#include "passes/offscreen_renderer.h"
#include "splat/sort.h"
#include "support/gpu_fixture.h"
#include "support/render_once.h"
#include "support/splat_reference.h"

#include "support/skip.h"
using namespace pbdsplat;

namespace {

render::FrameInputs flat_frame() {
    render::FrameInputs f;
    f.camera.eye = Vec3f(0.0f, 0.0f, 3.0f);
    f.camera.fov_y_degrees = 90.0f;  // strong perspective: off-axis splats project stretched
    f.background = Vec4f(0.0f, 0.0f, 0.0f, 1.0f);
    f.lighting.environment.sampling = render::EnvSampling::off;
    f.lighting.ambient = Vec3f(1.0f, 1.0f, 1.0f);
    f.lighting.intensity = 0.0f;
    f.lighting.specular = 0.0f;
    return f;
}

// Overlapping splats at distinct depths, on the axis, off it and near a corner of the view.
std::vector<splat::GaussianRecord> test_splats(float opacity_logit) {
    struct S {
        Vec3f p;
        Vec3f albedo;
        float scale;
    };
    const S list[] = {{{0.0f, 0.0f, 0.0f}, {0.9f, 0.2f, 0.1f}, 0.35f},  {{0.3f, 0.15f, 0.4f}, {0.1f, 0.8f, 0.3f}, 0.25f},
                      {{-0.25f, -0.2f, -0.5f}, {0.2f, 0.3f, 0.9f}, 0.4f}, {{2.2f, 1.1f, -0.3f}, {0.8f, 0.8f, 0.2f}, 0.3f},
                      {{-2.4f, -1.6f, 0.2f}, {0.7f, 0.2f, 0.8f}, 0.2f},   {{2.0f, -1.3f, 0.6f}, {0.3f, 0.9f, 0.9f}, 0.15f}};
    std::vector<splat::GaussianRecord> out;
    for (const S& s : list) {
        splat::Appearance a;
        a.albedo = s.albedo;
        a.scale = s.scale;
        a.opacity_logit = opacity_logit;
        out.push_back(splat::make_record(s.p, Vec3f(0.0f, 0.0f, 1.0f), a));
    }
    return out;
}

struct Agreement {
    size_t compared = 0, covered = 0, off = 0;  // off: pixels over the tolerance
    int worst = 0;
};

Agreement compare(const core::ImageRgba8& img, const std::vector<test::ReferencePixel>& ref, int tolerance, float rim_margin) {
    Agreement a;
    for (uint32_t y = 0; y < img.height; ++y)
        for (uint32_t x = 0; x < img.width; ++x) {
            const test::ReferencePixel& r = ref[size_t(y) * img.width + x];
            if (r.rim_margin < rim_margin) continue;  // the pixel centre sits on a rim: either side is right
            ++a.compared;
            if (r.color.maxCoeff() > 0.0f) ++a.covered;
            int d = 0;
            for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(int(img.at(x, y)[c]) - int(std::lround(r.color[c] * 255.0f))));
            a.worst = std::max(a.worst, d);
            if (d > tolerance) ++a.off;
        }
    return a;
}

struct Variant {
    render::SplatPath path;
    render::SplatCarrier carrier;
};
const Variant k_variants[] = {{render::SplatPath::geometry, render::SplatCarrier::quad},
                              {render::SplatPath::geometry, render::SplatCarrier::octagon},
                              {render::SplatPath::mesh, render::SplatCarrier::quad},
                              {render::SplatPath::mesh, render::SplatCarrier::octagon},
                              {render::SplatPath::vertex, render::SplatCarrier::quad}};
// Calls fn(variant) for each path and carrier the device has; says which it skips.
template <class Fn>
void for_each_variant(const gpu::Context& ctx, Fn&& fn) {
    for (const Variant& v : k_variants) {
        if (const std::string why = render::splat_path_unsupported(ctx.caps(), v.path); !why.empty()) {
            test::skip("the " + std::string(render::splat_path_name(v.path)) + " path: " + why);
            continue;
        }
        fn(v);
    }
}

std::string variant_name(const Variant& v) {
    return std::string(render::splat_path_name(v.path)) + (v.carrier == render::SplatCarrier::octagon ? " on octagons" : " on quads");
}

// Every path and carrier against `ref`: no pixel over `tolerance` (ignoring pixel centres within
// `rim` of a disc's edge), and more than `min_covered` pixels of the splats compared.
struct Expect {
    int tolerance = 1;
    float rim = 0.0f;
    size_t min_covered = 1000;
};
void check_every_variant(gpu::Context& ctx, const std::vector<splat::GaussianRecord>& records, const render::FrameInputs& frame,
                         const std::vector<test::ReferencePixel>& ref, uint32_t w, uint32_t h, const Expect& expect,
                         const std::string& label, std::span<const splat::GaussianShape> shapes = {},
                         const test::OccluderMesh* occluders = nullptr) {
    for_each_variant(ctx, [&](const Variant& v) {
        const auto img = test::render_once(ctx, records, frame, w, h, v.path, render::SplatShading::fragment, v.carrier, shapes, occluders);
        const Agreement a = compare(img, ref, expect.tolerance, expect.rim);
        INFO(variant_name(v) << ", " << label << ": " << a.off << " of " << a.compared << " pixels over " << expect.tolerance
                             << "/255, worst " << a.worst);
        MESSAGE(variant_name(v) << ", " << label << ": worst " << a.worst << "/255 over " << a.compared << " pixels");
        CHECK(a.covered > expect.min_covered);
        CHECK(a.off == 0);
    });
}


// Needles along x, y and 45 degrees in the view plane, one tilted in depth, one flat disc seen
// edge-on (the low-pass keeps it a line): the shapes a trained file holds.
std::pair<std::vector<splat::GaussianRecord>, std::vector<splat::GaussianShape>> test_needles(float opacity_logit) {
    struct N {
        Vec3f p;
        Vec3f albedo;
        Eigen::Matrix3f axes;
    };
    const float len = 0.6f, thin = 0.04f;
    auto rotated = [](float degrees, const Vec3f& axis) { return Eigen::AngleAxisf(math::radians(degrees), axis).toRotationMatrix(); };
    const Eigen::Matrix3f needle = Vec3f(len, thin, thin).asDiagonal();
    const N list[] = {{{-1.2f, 0.6f, 0.0f}, {0.9f, 0.2f, 0.1f}, needle},
                      {{1.2f, 0.6f, -0.2f}, {0.1f, 0.8f, 0.3f}, rotated(90.0f, Vec3f::UnitZ()) * needle},
                      {{0.0f, 0.0f, 0.3f}, {0.2f, 0.3f, 0.9f}, rotated(45.0f, Vec3f::UnitZ()) * needle},
                      {{-1.0f, -0.9f, 0.0f}, {0.8f, 0.8f, 0.2f}, rotated(60.0f, Vec3f::UnitY()) * needle},
                      {{1.2f, -0.9f, 0.1f}, {0.7f, 0.2f, 0.8f}, rotated(90.0f, Vec3f::UnitX()) * Eigen::Matrix3f(Vec3f(0.5f, 0.5f, 0.0f).asDiagonal())}};
    std::vector<splat::GaussianRecord> records;
    std::vector<splat::GaussianShape> shapes;
    for (const N& n : list) {
        splat::Appearance a;
        a.albedo = n.albedo;
        a.scale = splat::shape_reach(n.axes);
        a.opacity_logit = opacity_logit;
        records.push_back(splat::make_record(n.p, Vec3f(0.0f, 0.0f, 1.0f), a));
        shapes.push_back(splat::make_shape(n.axes));
    }
    return {records, shapes};
}

// A near plate over the left half of a far one, facing the eye, each carrying its splats at
// spacing h and its two triangles as occluders: the near plate's splats reach past its right
// edge over the far plate (an occluding contour), the far plate's lie behind the near one, and
// both reach past the far plate's outline.
struct TwoPlates {
    std::vector<splat::GaussianRecord> records;
    test::OccluderMesh mesh;
    float h = 0.1f;

    void plate(float x0, float x1, float y0, float y1, float z, const Vec3f& albedo, float opacity_logit) {
        const auto v = uint32_t(mesh.x.size());
        for (const Vec2f& c : {Vec2f(x0, y0), Vec2f(x1, y0), Vec2f(x1, y1), Vec2f(x0, y1)}) mesh.x.push_back({c.x(), c.y(), z, 1.0f});
        mesh.triangles.push_back({v, v + 1, v + 2}), mesh.triangles.push_back({v, v + 2, v + 3});
        splat::Appearance look;
        look.albedo = albedo;
        look.scale = 0.7f * h;
        look.opacity_logit = opacity_logit;
        for (float px = x0 + 0.5f * h; px < x1; px += h)
            for (float py = y0 + 0.5f * h; py < y1; py += h) records.push_back(splat::make_record({px, py, z}, {0, 0, 1}, look));
    }
    explicit TwoPlates(float opacity_logit) {
        plate(-1.0f, 0.0f, -0.6f, 0.6f, 0.5f, {0.9f, 0.2f, 0.1f}, opacity_logit);
        plate(-1.2f, 1.2f, -0.8f, 0.8f, 0.0f, {0.1f, 0.3f, 0.9f}, opacity_logit);
    }
};

} // namespace

TEST_SUITE("render/reference") {
    TEST_CASE("mesh occluders match the CPU reference, under normalised blending and the paper's disc, on every path") {
        // The reference casts each pixel's ray at the plates' triangles; the GPU rasterises them
        // into its occluder depth. Pixels on the mesh's outline, or with a splat at the ends of
        // the tolerance, are not judged.
        auto ctx = test::open_validated_context();
        const uint32_t w = 240, h = 160;
        for (const bool paper : {false, true}) {
            const TwoPlates plates(paper ? 8.0f : 1.5f);
            render::FrameInputs frame = flat_frame();
            frame.camera.fov_y_degrees = 45.0f;
            frame.background = Vec4f(0.1f, 0.15f, 0.2f, 1.0f);
            frame.style.footprint = paper ? render::Footprint::paper : render::Footprint::gaussian;
            frame.style.blend = paper ? render::Blend::over : render::Blend::normalised;
            frame.style.kappa = paper ? 0.0f : 2.0f;
            frame.style.mesh_occluders = true;
            frame.style.occluder_tolerance = 3.0f * 0.7f * plates.h;
            frame.style.occluder_push = 4.0f * 0.7f * plates.h;
            const auto ref = test::render_reference(plates.records, frame, w, h, {}, &plates.mesh);
            check_every_variant(*ctx, plates.records, frame, ref, w, h, {2, 0.05f, 5000}, paper ? "paper disc, mesh occluders" : "normalised, mesh occluders",
                                {}, &plates.mesh);
        }
        test::require_no_validation_messages(*ctx);
    }


    TEST_CASE("the CPU's shading (baked into exports) matches the splat pass's lighting") {
        auto ctx = test::open_validated_context();
        for (const render::EnvSampling sampling : {render::EnvSampling::position, render::EnvSampling::normal, render::EnvSampling::off}) {
            render::FrameInputs frame;
            frame.camera.eye = Vec3f(0.0f, 0.0f, 3.0f);
            frame.style.footprint = render::Footprint::paper;  // one flat disc, shaded per fragment
            frame.lighting.environment.sampling = sampling;
            frame.lighting.environment.center = Vec3f(0.0f, -0.5f, 0.0f);
            frame.lighting.environment.intensity = 0.4f;
            frame.lighting.intensity = 0.35f;  // mid-range colours: nothing clamps at 255
            frame.lighting.specular = 0.2f;
            render::Light point;
            point.position = Vec3f(1.0f, 1.0f, 1.5f);
            point.color = Vec3f(0.15f, 0.25f, 0.4f);
            frame.lighting.lights.push_back(point);
            splat::Appearance a;
            a.albedo = Vec3f(0.5f, 0.35f, 0.2f);
            a.scale = 0.3f;
            a.opacity_logit = 8.0f;
            const Vec3f normal = Vec3f(0.3f, 0.4f, 1.0f).normalized();
            const std::vector<splat::GaussianRecord> one = {splat::make_record(Vec3f::Zero(), normal, a)};
            const auto img = test::render_once(*ctx, one, frame, 64, 64);
            // The renderer's sky for the default sun, as the CPU makes it.
            const render::EnvironmentMap map = render::procedural_sky(render::RendererOptions{}.sky_sun);
            render::CpuShading shading;
            shading.lighting = &frame.lighting;
            shading.map = &map;
            shading.sh = render::irradiance_sh(map);
            shading.eye = frame.camera.eye;
            const Vec3f albedo = Vec3f(one[0].color[0], one[0].color[1], one[0].color[2]) / 255.0f;
            const Vec3f cpu = render::shade_cpu(shading, albedo, splat::decode_octahedral(one[0].normal_oct), Vec3f::Zero());
            const uint8_t* gpu = img.at(32, 32);  // the pixel at the disc's centre
            MESSAGE("sampling " << std::string(render::env_sampling_name(sampling)) << ": GPU " << int(gpu[0]) << " " << int(gpu[1]) << " "
                             << int(gpu[2]) << ", CPU " << cpu.transpose() * 255.0f);
            CHECK(cpu.maxCoeff() < 0.95f);  // unclamped: the comparison means something
            CHECK(cpu.minCoeff() > 0.05f);  // unclamped: measured at least 65 of 255
            for (int c = 0; c < 3; ++c) CHECK(std::abs(int(gpu[c]) - int(std::lround(std::clamp(cpu[c], 0.0f, 1.0f) * 255.0f))) <= 3);
        }
        test::require_no_validation_messages(*ctx);
    }

    TEST_CASE("anisotropic splats match a CPU EWA reference, in both footprints, on every path") {
        auto ctx = test::open_validated_context();
        const uint32_t w = 240, h = 160;
        for (const render::Footprint footprint : {render::Footprint::paper, render::Footprint::gaussian}) {
            render::FrameInputs frame = flat_frame();
            frame.style.footprint = footprint;
            frame.style.order = render::SplatOrder::cpu;
            auto [records, shapes] = test_needles(footprint == render::Footprint::paper ? 8.0f : 1.0f);
            splat::SortScratch scratch;
            splat::sort_far_to_near(records, shapes, math::look_at(frame.camera.eye, frame.camera.target, frame.camera.up), scratch);
            const auto ref = test::render_reference(records, frame, w, h, shapes);
            const bool paper = footprint == render::Footprint::paper;
            check_every_variant(*ctx, records, frame, ref, w, h, {paper ? 1 : 2, paper ? 0.02f : 0.0f, 300},
                                render::footprint_name(footprint), shapes);
            // Drawn round, the same records miss the reference badly: the test sees shapes.
            const auto round = test::render_once(*ctx, records, frame, w, h);
            CHECK(compare(round, ref, 2, 0.02f).off > 200);
        }
        test::require_no_validation_messages(*ctx);
    }

    TEST_CASE("surfels are the Gaussian flattened onto its normal's plane: the CPU EWA reference of those axes, on every path") {
        // Each splat's normal tilted differently: facing the eye, 60 degrees off, edge-on (a
        // line, kept a pixel wide by the low-pass), and off axis. The reference gets the
        // flattened covariance as explicit axes (any tangent basis: the disc is round in its
        // plane); the renderer builds it from the record's normal alone.
        auto ctx = test::open_validated_context();
        const uint32_t w = 240, h = 160;
        const float thickness = 0.1f;
        const Vec3f normals[] = {Vec3f(0.0f, 0.0f, 1.0f), Vec3f(std::sin(math::radians(60.0f)), 0.0f, std::cos(math::radians(60.0f))),
                                 Vec3f(0.0f, 1.0f, 0.0f), Vec3f(0.3f, -0.5f, 0.8f).normalized(), Vec3f(-0.7f, 0.7f, 0.1f).normalized(),
                                 Vec3f(0.0f, 0.6f, 0.8f)};
        for (const render::Footprint footprint : {render::Footprint::paper, render::Footprint::gaussian}) {
            const bool paper = footprint == render::Footprint::paper;
            render::FrameInputs frame = flat_frame();
            frame.style.footprint = footprint;
            frame.style.order = render::SplatOrder::cpu;
            frame.style.surfel_thickness = thickness;
            std::vector<splat::GaussianRecord> records = test_splats(paper ? 8.0f : 1.0f);
            std::vector<splat::GaussianShape> shapes;
            for (size_t i = 0; i < records.size(); ++i) {
                const Vec3f n = normals[i].normalized();
                splat::encode_octahedral(n, records[i].normal_oct);
                // The normal as the GPU will read it back, so both flatten along the same axis.
                const Vec3f m = splat::decode_octahedral(records[i].normal_oct);
                const Vec3f t1 = m.unitOrthogonal(), t2 = m.cross(t1);
                const float s0 = splat::half_to_float(records[i].scale_half);
                Eigen::Matrix3f axes;
                axes << s0 * t1, s0 * t2, thickness * s0 * m;
                shapes.push_back(splat::make_shape(axes));
            }
            splat::SortScratch scratch;
            splat::sort_far_to_near(records, shapes, math::look_at(frame.camera.eye, frame.camera.target, frame.camera.up), scratch);
            render::FrameInputs reference_frame = frame;
            reference_frame.style.surfel_thickness = 0.0f;  // the reference reads the axes
            const auto ref = test::render_reference(records, reference_frame, w, h, shapes);
            check_every_variant(*ctx, records, frame, ref, w, h, {paper ? 1 : 2, paper ? 0.02f : 0.0f, 300},
                                std::string("surfels, ") + render::footprint_name(footprint));
            // Drawn round, the same records miss the reference badly: the test sees the flattening.
            const auto round = test::render_once(*ctx, records, reference_frame, w, h);
            CHECK(compare(round, ref, 2, 0.02f).off > 200);
        }
        test::require_no_validation_messages(*ctx);
    }

    TEST_CASE("the paper's disc matches a CPU reference of eqs. 14-23 within 1 LSB, on every path") {
        auto ctx = test::open_validated_context();
        const uint32_t w = 240, h = 160;
        for (const Vec2f& sharpness : {Vec2f(1.0f, 1.0f), Vec2f(0.7f, 0.7f)}) {
            render::FrameInputs frame = flat_frame();
            frame.style.footprint = render::Footprint::paper;
            frame.style.sharpness = sharpness;
            const auto records = test_splats(8.0f);  // opaque: every disc pixel kept by the dither
            const auto ref = test::render_reference(records, frame, w, h);
            check_every_variant(*ctx, records, frame, ref, w, h, {1, 0.02f, 1000}, "sharpness " + std::to_string(sharpness.x()));
        }
        test::require_no_validation_messages(*ctx);
    }

    TEST_CASE("normalised blending matches the CPU reference of its definition, on every path") {
        // The scenes' look: soft Gaussians averaged over the front surface. Overlapping splats at
        // distinct depths, opaque enough that the nearer cores hide what lies behind them.
        auto ctx = test::open_validated_context();
        const uint32_t w = 240, h = 160;
        for (const float kappa : {2.0f, 0.0f}) {
            render::FrameInputs frame = flat_frame();
            frame.style.footprint = render::Footprint::gaussian;
            frame.style.blend = render::Blend::normalised;
            frame.style.kappa = kappa;
            frame.background = Vec4f(0.1f, 0.15f, 0.2f, 1.0f);  // shows where coverage is partial
            const auto records = test_splats(1.0f);
            const auto ref = test::render_reference(records, frame, w, h);
            // Within 1/255 on every path (2026-11-29); pixels on an opaque core's edge (within 5 % of
            // depth_min_alpha) left out: which side of it the GPU's rasteriser puts them is rounding.
            check_every_variant(*ctx, records, frame, ref, w, h, {2, 0.05f, 2000}, "normalised, kappa " + std::to_string(kappa));
        }
        test::require_no_validation_messages(*ctx);
    }

    TEST_CASE("the Gaussian, sorted over and additive, matches the CPU reference within 2 LSB, on every path") {
        auto ctx = test::open_validated_context();
        const uint32_t w = 240, h = 160;
        for (const render::Blend blend : {render::Blend::over, render::Blend::additive}) {
            render::FrameInputs frame = flat_frame();
            frame.style.footprint = render::Footprint::gaussian;
            frame.style.blend = blend;
            frame.style.order = render::SplatOrder::cpu;  // the records arrive far to near
            auto records = test_splats(1.0f);              // translucent: every layer shows
            splat::SortScratch scratch;
            splat::sort_far_to_near(records, math::look_at(frame.camera.eye, frame.camera.target, frame.camera.up), scratch);
            const auto ref = test::render_reference(records, frame, w, h);
            // Each blend rounds to 8 bits on the GPU; a few layers drift by up to 2/255.
            check_every_variant(*ctx, records, frame, ref, w, h, {2, 0.0f, 2000}, blend == render::Blend::additive ? "additive" : "over");
        }
        test::require_no_validation_messages(*ctx);
    }
}
