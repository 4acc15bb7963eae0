#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "core/math.h"
#include "render/frame_uniforms.h"
#include "render/screen_bounds.h"

using namespace pbdsplat;

namespace {

splat::GaussianRecord record_at(const Vec3f& p, float scale) {
    splat::GaussianRecord r{};
    r.position[0] = p.x(), r.position[1] = p.y(), r.position[2] = p.z();
    r.scale_half = splat::float_to_half(scale);
    return r;
}

// Where `p` lands on the width x height target under the frame's camera.
Vec2f pixel_of(const Vec3f& p, const render::FrameInputs& f, uint32_t width, uint32_t height) {
    const render::Camera& c = f.camera;
    const Vec4f q = math::perspective(math::radians(c.fov_y_degrees), float(width) / float(height), c.z_near, c.z_far) *
                    math::look_at(c.eye, c.target, c.up) * Vec4f(p.x(), p.y(), p.z(), 1.0f);
    return {(q.x() / q.w() * 0.5f + 0.5f) * float(width), (q.y() / q.w() * 0.5f + 0.5f) * float(height)};
}

bool inside(const render::PixelRect& r, const Vec2f& px) {
    return px.x() >= float(r.x) && px.x() <= float(r.x + r.width) && px.y() >= float(r.y) && px.y() <= float(r.y + r.height);
}

} // namespace

TEST_SUITE("render/screen_bounds") {
    TEST_CASE("the rectangle holds every splat's reach and not much more; behind the eye or unknown, the whole target") {
        const uint32_t w = 320, h = 180;
        render::FrameInputs f;
        f.camera.eye = {0.0f, 0.0f, 4.0f};
        f.camera.target = {0.0f, 0.0f, 0.0f};
        f.style.footprint = render::Footprint::gaussian;
        f.style.kappa = 2.0f;
        const float scale = 0.05f;
        std::vector<splat::GaussianRecord> records;
        for (int i = 0; i < 64; ++i) {
            const float a = 2.0f * float(M_PI) * float(i) / 64.0f;
            records.push_back(record_at({0.6f + 0.2f * std::cos(a), -0.1f + 0.2f * std::sin(a), 0.1f * std::sin(3.0f * a)}, scale));
        }
        const render::SplatBounds b = render::splat_bounds(records);
        CHECK(b.max_scale == doctest::Approx(scale).epsilon(1e-3));
        const render::PixelRect r = render::splat_screen_rect(b, f, w, h);
        // Each splat's reach, in the four directions across the view plane, lies inside.
        const float reach = render::splat_reach_bound(f.style) * scale;
        for (const auto& rec : records) {
            const Vec3f p(rec.position[0], rec.position[1], rec.position[2]);
            for (const Vec3f& d : {Vec3f(reach, 0, 0), Vec3f(-reach, 0, 0), Vec3f(0, reach, 0), Vec3f(0, -reach, 0)})
                CHECK(inside(r, pixel_of(p + d, f, w, h)));
        }
        // A small body well off centre: a small part of the target, away from its corner.
        CHECK(double(r.width) * r.height < 0.25 * double(w) * h);
        CHECK(r.x > w / 2);
        CHECK(r.x + r.width <= w);
        CHECK(r.y + r.height <= h);

        // One splat behind the eye: its projection wraps, so the whole target.
        records.push_back(record_at({0.0f, 0.0f, 5.0f}, scale));
        const render::PixelRect whole = render::splat_screen_rect(render::splat_bounds(records), f, w, h);
        CHECK(whole.x == 0);
        CHECK(whole.y == 0);
        CHECK(whole.width == w);
        CHECK(whole.height == h);
        // A NaN centre is clipped away when drawn: left out of the box.
        records.back() = record_at({NAN, 0.0f, 0.0f}, scale);
        const render::PixelRect without_nan = render::splat_screen_rect(render::splat_bounds(records), f, w, h);
        CHECK(without_nan.x == r.x);
        CHECK(without_nan.width == r.width);
        // An infinite scale: its reach is unknown, so the whole target.
        records.back() = record_at({0.0f, 0.0f, 0.0f}, INFINITY);
        const render::PixelRect unknown = render::splat_screen_rect(render::splat_bounds(records), f, w, h);
        CHECK(unknown.width == w);
        CHECK(unknown.height == h);
        // No splats, or all off to the side: one pixel, still a valid area to begin a pass on.
        const render::PixelRect none = render::splat_screen_rect(render::splat_bounds({}), f, w, h);
        CHECK(none.width == 1);
        CHECK(none.height == 1);
        const std::vector<splat::GaussianRecord> aside = {record_at({40.0f, 0.0f, 0.0f}, scale)};
        const render::PixelRect off = render::splat_screen_rect(render::splat_bounds(aside), f, w, h);
        CHECK(off.width == 1);
        CHECK(off.height == 1);
        CHECK(off.x < w);
        CHECK(off.y < h);
    }
}
