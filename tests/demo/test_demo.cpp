#include <doctest/doctest.h>

#include <cstdlib>
#include <filesystem>
#include <vector>

#include "core/image.h"
#include "demo/app.h"
#include "demo/capture_app.h"
#include "splat/ply.h"
#include "demo/script.h"
#include "scene/scene_file.h"

#include "support/skip.h"
#include "support/why.h"
using namespace pbdsplat;

namespace {

// Connected regions (4-neighbours) of pixels that differ from the corner pixel (the
// background), ignoring specks smaller than `min_pixels`.
size_t count_regions(const core::ImageRgba8& img, size_t min_pixels) {
    const uint8_t* bg = img.at(0, 0);
    auto is_body = [&](uint32_t x, uint32_t y) {
        const uint8_t* p = img.at(x, y);
        return std::abs(int(p[0]) - int(bg[0])) + std::abs(int(p[1]) - int(bg[1])) + std::abs(int(p[2]) - int(bg[2])) > 24;
    };
    std::vector<uint8_t> seen(size_t(img.width) * img.height, 0);
    size_t regions = 0;
    std::vector<std::pair<uint32_t, uint32_t>> stack;
    for (uint32_t y = 0; y < img.height; ++y)
        for (uint32_t x = 0; x < img.width; ++x) {
            if (seen[size_t(y) * img.width + x] || !is_body(x, y)) continue;
            size_t size = 0;
            stack.assign(1, {x, y});
            seen[size_t(y) * img.width + x] = 1;
            while (!stack.empty()) {
                const auto [px, py] = stack.back();
                stack.pop_back();
                ++size;
                const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
                for (int k = 0; k < 4; ++k) {
                    const int qx = int(px) + dx[k], qy = int(py) + dy[k];
                    if (qx < 0 || qy < 0 || qx >= int(img.width) || qy >= int(img.height)) continue;
                    const size_t i = size_t(qy) * img.width + size_t(qx);
                    if (seen[i] || !is_body(uint32_t(qx), uint32_t(qy))) continue;
                    seen[i] = 1;
                    stack.emplace_back(uint32_t(qx), uint32_t(qy));
                }
            }
            if (size >= min_pixels) ++regions;
        }
    return regions;
}

bool have_display() {
    const char* d = std::getenv("DISPLAY");
    const char* w = std::getenv("WAYLAND_DISPLAY");
    return (d && *d) || (w && *w);
}

} // namespace

TEST_SUITE("demo/script") {
    TEST_CASE("input scripts turn actions into the window's events, and name the line of a mistake") {
        auto s = demo::InputScript::parse("# c\n3 cut 10 20 30 40\n20 key p\n30 drag 0 0 10 0 2\n", "t.script");
        REQUIRE_MESSAGE(s.ok(), test::why(s));
        const auto press = s->events_at(3);
        REQUIRE(press.size() == 1);
        CHECK(press[0].kind == demo::InputEvent::Kind::press);
        CHECK(press[0].button == 1);
        CHECK(s->events_at(8).back().kind == demo::InputEvent::Kind::release);  // cut: 4 moves, then release
        CHECK(s->events_at(20).at(0).key == 'P');
        CHECK(s->events_at(31).at(0).position.x() == doctest::Approx(5.0f));  // half way in two frames
        CHECK(s->events_at(33).at(0).kind == demo::InputEvent::Kind::release);
        for (const char* bad : {"x cut 1 2 3 4", "3 cut 1 2 3", "3 key nosuchkey", "3 fly 1", "3 drag 1 2 3 4 0", "-1 key p"}) {
            auto r = demo::InputScript::parse(std::string("# ok\n") + bad + "\n", "bad.script");
            REQUIRE_FALSE(r.ok());
            CHECK_MESSAGE(r.error().to_string().find("bad.script:2:") != std::string::npos, r.error().to_string());
        }
    }
}

TEST_SUITE("demo/window") {
    TEST_CASE("the demo runs a scripted cut and drag in a window and shows the body in two pieces") {
        if (!have_display()) {
            test::skip("no display (ctest runs this suite under xvfb-run)");
            return;
        }
        auto scene = scene::load_scene(std::string(PBDSPLAT_TEST_SCENES_DIR) + "/demo_cut.toml");
        REQUIRE_MESSAGE(scene.ok(), test::why(scene));
        demo::DemoOptions o;
        o.scene = scene.value();
        o.frames = 60;
        o.screenshot_at = 59;
        o.screenshot_path = (std::filesystem::path(PBDSPLAT_TEST_OUTPUT_DIR) / "demo_cut_in_two.png").string();
        std::filesystem::create_directories(PBDSPLAT_TEST_OUTPUT_DIR);
        o.script_path = std::string(PBDSPLAT_TEST_DEMO_DIR) + "/cut_in_two.script";
        o.vsync = false;
        o.validation = true;
        o.hud = true;  // drawn over the window, not into the screenshot: exercised all the same
        auto report = demo::run_demo(o);
        REQUIRE_MESSAGE(report.ok(), test::why(report));
        CHECK(report->frames == 60);
        CHECK(report->cuts == 1);
        CHECK(report->pieces == 2);
        CHECK(report->validation_messages == 0);
        REQUIRE(report->screenshot == o.screenshot_path);
        auto img = core::read_image(o.screenshot_path);
        REQUIRE_MESSAGE(img.ok(), test::why(img));
        CHECK(img->width == 320);
        CHECK(img->height == 240);
        const size_t regions = count_regions(img.value(), 200);
        MESSAGE("splat mask regions in the screenshot: " << regions);
        CHECK(regions == 2);
    }

    TEST_CASE("a capture (.ply of Gaussians) is shown in the window, sorted and drawn each frame, without a simulation") {
        if (!have_display()) {
            test::skip("no display (ctest runs this suite under xvfb-run)");
            return;
        }
        // Two clusters of flat, tilted Gaussians: drawn as trained (anisotropic, far to near).
        std::vector<splat::GaussianRecord> records;
        std::vector<splat::GaussianShape> shapes;
        for (int i = 0; i < 400; ++i) {
            const float a = 0.157f * float(i), side = i % 2 ? 0.6f : -0.6f;
            const Vec3f p(side + 0.3f * std::cos(a), 0.3f * std::sin(a), 0.05f * std::sin(3.0f * a));
            const Eigen::Matrix3f axes = Vec3f(0.08f, 0.05f, 0.01f).asDiagonal();
            splat::Appearance look;
            look.albedo = i % 2 ? Vec3f(0.9f, 0.4f, 0.2f) : Vec3f(0.2f, 0.5f, 0.9f);
            look.scale = splat::shape_reach(axes);
            records.push_back(splat::make_record(p, Vec3f::UnitZ(), look));
            shapes.push_back(splat::make_shape(axes));
        }
        std::filesystem::create_directories(PBDSPLAT_TEST_OUTPUT_DIR);
        const std::string path = (std::filesystem::path(PBDSPLAT_TEST_OUTPUT_DIR) / "window_capture.ply").string();
        REQUIRE(splat::write_ply(path, records, shapes).ok());
        demo::CaptureOptions o;
        o.path = path;
        o.width = 320;
        o.height = 240;
        o.frames = 8;
        o.screenshot_at = 7;
        o.screenshot_path = (std::filesystem::path(PBDSPLAT_TEST_OUTPUT_DIR) / "window_capture.png").string();
        o.vsync = false;
        o.validation = true;
        for (const bool gpu_sort : {false, true}) {
            o.gpu_sort = gpu_sort;
            auto report = demo::run_capture(o);
            REQUIRE_MESSAGE(report.ok(), test::why(report));
            CHECK(report->frames == 8);
            CHECK(report->gaussians == records.size());
            CHECK(report->particles == 0);
            CHECK(report->validation_messages == 0);
            auto img = core::read_image(o.screenshot_path);
            REQUIRE_MESSAGE(img.ok(), test::why(img));
            CHECK(img->width == 320);
            // Both rings show, apart (the camera turns slowly about their common centre).
            const size_t regions = count_regions(img.value(), 100);
            MESSAGE((gpu_sort ? "GPU" : "CPU") << " sort: regions in the capture's screenshot: " << regions);
            CHECK(regions == 2);
        }
        // A missing file says so, before any window opens.
        o.path = (std::filesystem::path(PBDSPLAT_TEST_OUTPUT_DIR) / "no_such_capture.ply").string();
        auto missing = demo::run_capture(o);
        REQUIRE_FALSE(missing.ok());
        CHECK(missing.error().to_string().find("no_such_capture.ply") != std::string::npos);
    }
}
