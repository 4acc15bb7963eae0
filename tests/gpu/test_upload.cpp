#include <doctest/doctest.h>

#include "gpu/upload_ring.h"
#include "passes/offscreen_renderer.h"
#include "scene/builtin_scene.h"
#include "support/gpu_fixture.h"

using namespace pbdsplat;

TEST_SUITE("gpu/upload") {
    TEST_CASE("the staging ring wraps, and refuses to overwrite frames still in flight") {
        auto ctx = test::open_validated_context();
        auto ring = gpu::UploadRing::create(*ctx, 1000);
        REQUIRE(ring.ok());
        auto a = ring->allocate(1, 400);
        REQUIRE(a.ok());
        CHECK(a->offset == 0);
        auto b = ring->allocate(2, 400);
        REQUIRE(b.ok());
        CHECK(b->offset == 400);
        CHECK_FALSE(ring->allocate(3, 400).ok());  // frames 1 and 2 still hold 800 bytes
        ring->retire(1);                           // frame 1 done: its 400 bytes at the front are free
        auto c = ring->allocate(3, 300);           // does not fit at the tail (200 left): wraps to 0
        REQUIRE(c.ok());
        CHECK(c->offset == 0);
        CHECK_FALSE(ring->allocate(3, 200).ok());  // 0..300 and 400..800 held, the 200-byte tail was skipped
        ring->retire(3);
        CHECK(ring->in_flight_bytes() == 0);
        CHECK_FALSE(ring->allocate(4, 2000).ok());  // larger than the ring
        test::require_no_validation_messages(*ctx);
    }

    // The two upload paths must produce the same image; so must uploading only changed ranges.
    TEST_CASE("staged, direct and partial uploads give identical images") {
        auto ctx = test::open_validated_context();
        auto scene = scene::make_builtin_scene(3);
        render::RendererOptions o;
        o.width = 160;
        o.height = 120;
        o.max_splats = uint32_t(scene.records.size());

        std::vector<gpu::UploadPath> paths = {gpu::UploadPath::staged};
        if (ctx->caps().unified_memory) paths.push_back(gpu::UploadPath::direct);
        std::vector<core::ImageRgba8> images;
        for (gpu::UploadPath path : paths) {
            o.upload_path = path;
            auto r = passes::OffscreenRenderer::create(*ctx, o);
            REQUIRE(r.ok());
            CHECK(r.value()->upload_path() == path);
            // Changed ranges are relative to the previous frame. Frame 2 moves the first 100
            // splats away and frame 3 puts them back, each uploading only that range; frame 4
            // changes an unrelated range. With two frames in flight, the direct path's second
            // buffer must still catch up on frame 3's change, or the image shows moved splats.
            auto moved = scene.records;
            for (size_t i = 0; i < 100; ++i) moved[i].position[0] += 5.0f;
            const gpu::ByteRange first{0, 100 * sizeof(splat::GaussianRecord)};
            const gpu::ByteRange last{(scene.records.size() - 10) * sizeof(splat::GaussianRecord),
                                      10 * sizeof(splat::GaussianRecord)};
            REQUIRE(r.value()->render(scene.records, scene.frame).ok());
            REQUIRE(r.value()->render(moved, scene.frame, {&first, 1}).ok());
            REQUIRE(r.value()->render(scene.records, scene.frame, {&first, 1}).ok());
            REQUIRE(r.value()->render(scene.records, scene.frame, {&last, 1}).ok());
            auto img = r.value()->finish();
            REQUIRE(img.ok());
            images.push_back(std::move(img).value());
        }
        // Reference: one full upload.
        o.upload_path.reset();
        auto ref = passes::OffscreenRenderer::create(*ctx, o);
        REQUIRE(ref.ok());
        REQUIRE(ref.value()->render(scene.records, scene.frame).ok());
        auto expected = ref.value()->finish();
        REQUIRE(expected.ok());
        for (const auto& img : images) CHECK(img.pixels == expected->pixels);
        test::require_no_validation_messages(*ctx);
    }

    TEST_CASE("more Gaussians than the renderer holds is an error, and the renderer stays usable") {
        auto ctx = test::open_validated_context();
        auto scene = scene::make_builtin_scene(2);
        render::RendererOptions o;
        o.width = 64;
        o.height = 48;
        o.max_splats = 100;
        auto r = passes::OffscreenRenderer::create(*ctx, o);
        REQUIRE(r.ok());
        const auto s = r.value()->render(scene.records, scene.frame);  // 162 records
        REQUIRE_FALSE(s.ok());
        CHECK(s.error().message.find("exceed the renderer's capacity of 100") != std::string::npos);
        REQUIRE(r.value()->render(std::span(scene.records).first(100), scene.frame).ok());
        CHECK(r.value()->finish().ok());
        test::require_no_validation_messages(*ctx);
    }
}
