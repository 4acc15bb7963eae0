#include <doctest/doctest.h>

#include "scene/framing.h"
#include "scene/scene_file.h"
#include "scene/scene_runtime.h"
#include "support/why.h"

using namespace pbdsplat;

namespace {
mesh::Bounds box(const Vec3f& centre, float half) { return {centre - Vec3f::Constant(half), centre + Vec3f::Constant(half)}; }
std::vector<Vec3f> corners(const mesh::Bounds& b) {
    std::vector<Vec3f> out;
    for (int c = 0; c < 8; ++c) out.emplace_back((c & 1) ? b.max.x() : b.min.x(), (c & 2) ? b.max.y() : b.min.y(), (c & 4) ? b.max.z() : b.min.z());
    return out;
}

// Where a runtime's particles are.
std::vector<Vec3f> particles(const scene::SceneRuntime& rt) {
    std::vector<Vec3f> out;
    for (const auto& p : rt.body().particles.x) out.emplace_back(p.head<3>());
    return out;
}
constexpr float k_aspect = 16.0f / 9.0f;
} // namespace

TEST_SUITE("scene/framing") {
    TEST_CASE("framing: the default camera sees a model fitted at the origin; a framed camera sees any box, near or far, small or large") {
        const render::Camera lens;
        // The unit ball's box from 3 units: its top corners at 0.58 / 2.42 = 0.24 of the frame's
        // half-height tangent 0.41, inside.
        CHECK(scene::camera_sees(lens, corners(box(Vec3f::Zero(), 0.58f)), k_aspect));
        CHECK_FALSE(scene::camera_sees(lens, corners(box(Vec3f(0.0f, 3.0f, 0.0f), 0.5f)), k_aspect));   // above the view
        CHECK_FALSE(scene::camera_sees(lens, corners(box(Vec3f(0.0f, 0.0f, 4.0f), 0.5f)), k_aspect));   // behind the eye
        CHECK_FALSE(scene::camera_sees(lens, corners(box(Vec3f::Zero(), 3.0f)), k_aspect));             // around the eye
        // A 2 cm model at the origin is in view, but a speck: asked to span a tenth of the view, it does not.
        CHECK(scene::camera_sees(lens, corners(box(Vec3f::Zero(), 0.01f)), k_aspect));
        CHECK_FALSE(scene::camera_sees(lens, corners(box(Vec3f::Zero(), 0.01f)), k_aspect, 0.95f, 0.1f));
        CHECK(scene::camera_sees(lens, corners(box(Vec3f::Zero(), 0.58f)), k_aspect, 0.95f, 0.1f));
        for (const float half : {0.01f, 0.5f, 3.0f, 50.0f})
            for (const Vec3f& c : {Vec3f(Vec3f::Zero()), Vec3f(10.0f, 2.0f, -7.0f), Vec3f(-3.0f, 40.0f, 5.0f)})
                for (const float aspect : {k_aspect, 0.5f}) {
                    CAPTURE(half);
                    CAPTURE(aspect);
                    const render::Camera framed = scene::framing_camera(box(c, half), lens, aspect);
                    CHECK(framed.target.isApprox(c));
                    CHECK(framed.eye.y() > framed.target.y());  // from a little above
                    // The box's bounding sphere just fills the narrower side: its corners within it.
                    CHECK(scene::camera_sees(framed, corners(box(c, half)), aspect, 1.001f));
                    // Not from so far that the box is a speck: its sphere fills the narrower side.
                    CHECK_FALSE(scene::camera_sees(framed, corners(box(c, half)), aspect, 0.5f));
                }
    }

    TEST_CASE("a scene of [[bodies]] alone takes its first body as [model] (no default ball beside them) and a camera that frames them") {
        const char* text = R"(
[[bodies]]
mesh = "icosphere:2"
translate = [4, 3, -2]
color = [0.1, 0.2, 0.3]
particles = 0
[[bodies]]
mesh = "box:4"
translate = [6, 3, -2]
)";
        auto sc = scene::parse_scene(text, "bodies_only.toml");
        REQUIRE_MESSAGE(sc.ok(), test::why(sc));
        CHECK(sc->model.mesh == "icosphere:2");
        REQUIRE(sc->bodies.size() == 1);
        CHECK(sc->bodies[0].model.mesh == "box:4");
        REQUIRE(sc->model_own.color);
        CHECK(sc->model_own.color->isApprox(Vec3f(0.1f, 0.2f, 0.3f)));
        CHECK(sc->model_own.particles == 0u);
        CHECK_FALSE(sc->render.camera_given);
        // Printed and read again, the same two models with the first one's colour.
        auto again = scene::parse_scene(scene::to_toml(sc.value()), "again.toml");
        REQUIRE_MESSAGE(again.ok(), test::why(again));
        CHECK(again->model.mesh == "icosphere:2");
        CHECK(again->bodies.size() == 1);
        REQUIRE(again->model_own.color);
        CHECK(again->model_own.color->isApprox(Vec3f(0.1f, 0.2f, 0.3f)));
        CHECK_FALSE(again->render.camera_given);

        auto rt = scene::SceneRuntime::create(sc.value(), {});
        REQUIRE_MESSAGE(rt.ok(), test::why(rt));
        const sim::SoftBody& b = rt.value()->body();
        CHECK(b.pieces == 2);  // the ball and the box, nothing else
        REQUIRE(b.colors.size() == b.particle_count());
        CHECK(b.colors[0].isApprox(Vec3f(0.1f, 0.2f, 0.3f)));
        // The default view, from (0, 0, 3) at the origin, misses them; the runtime's camera sees them.
        CHECK_FALSE(scene::camera_sees(render::Camera{}, particles(*rt.value()), k_aspect));
        CHECK(scene::camera_sees(rt.value()->camera(), particles(*rt.value()), k_aspect, 1.001f));

        // A camera the file places stays where it is put, whatever it sees.
        auto placed = scene::parse_scene(std::string(text) + "[render.camera]\neye = [0, 0, 5]\n", "placed.toml");
        REQUIRE_MESSAGE(placed.ok(), test::why(placed));
        CHECK(placed->render.camera_given);
        auto rt_placed = scene::SceneRuntime::create(placed.value(), {});
        REQUIRE_MESSAGE(rt_placed.ok(), test::why(rt_placed));
        CHECK(rt_placed.value()->camera().eye.isApprox(Vec3f(0.0f, 0.0f, 5.0f)));
        // One model at the origin keeps the default view, which sees it (a unit ball from 3 units:
        // its outline 19.5 degrees off the axis, the frame's half-height 22.5).
        auto one = scene::parse_scene("[model]\nmesh = \"icosphere:2\"\n", "one.toml");
        REQUIRE(one.ok());
        auto rt_one = scene::SceneRuntime::create(one.value(), {});
        REQUIRE_MESSAGE(rt_one.ok(), test::why(rt_one));
        CHECK(rt_one.value()->camera().eye.isApprox(render::Camera{}.eye));
    }

    TEST_CASE("one model's colour, in [model] or a lone [[bodies]] entry, is the material's") {
        for (const char* text : {"[model]\nmesh = \"icosphere:1\"\ncolor = [0.2, 0.4, 0.6]\n",
                                 "[[bodies]]\nmesh = \"icosphere:1\"\ncolor = [0.2, 0.4, 0.6]\n"}) {
            CAPTURE(text);
            auto sc = scene::parse_scene(text, "one.toml");
            REQUIRE_MESSAGE(sc.ok(), test::why(sc));
            CHECK(sc->bodies.empty());
            CHECK_FALSE(sc->model_own.color);
            CHECK(sc->material.color.isApprox(Vec3f(0.2f, 0.4f, 0.6f)));
        }
    }
}
