#include <doctest/doctest.h>

#include "gpu/buffer.h"
#include "support/gpu_fixture.h"
#include "support/why.h"

using namespace pbdsplat;

TEST_SUITE("gpu/context") {
    TEST_CASE("the device reports what the splat pass needs") {
        auto ctx = test::open_validated_context();
        const auto& c = ctx->caps();
        CHECK_FALSE(c.name.empty());
        CHECK(c.api_version >= VK_API_VERSION_1_3);
        CHECK(c.geometry_shader);
        CHECK(c.subgroup_size >= 1);
        MESSAGE("device: " << c.name << ", driver: " << c.driver << ", mesh shader: " << std::string(c.mesh_shader ? "yes" : "no"));
        test::require_no_validation_messages(*ctx);
    }

    TEST_CASE("an object leaked past the device's end is reported at teardown, after the last in-test check") {
        gpu::ContextOptions o;
        o.instance.validation = true;
        auto ctx = gpu::Context::create(o);
        REQUIRE_MESSAGE(ctx.ok(), test::why(ctx));
        const auto log = ctx.value()->instance().shared_validation_log();
        VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
        info.size = 256;
        info.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
        VkBuffer leaked = VK_NULL_HANDLE;
        REQUIRE(vkCreateBuffer(ctx.value()->vk(), &info, nullptr, &leaked) == VK_SUCCESS);
        CHECK(log->count() == 0);  // what a check at the end of the test body would see
        ctx.value().reset();       // vkDestroyDevice with the buffer still alive
        MESSAGE("teardown reported " << log->count() << " message(s)" << (log->count() ? ": " + log->messages().front() : ""));
        CHECK(log->count() > 0);  // what ValidatedContext's destructor fails the test on
    }

    TEST_CASE("a device name that matches nothing is a clear error") {
        gpu::ContextOptions o;
        o.device.name_filter = "no-such-device-xyz";
        auto ctx = gpu::Context::create(o);
        REQUIRE_FALSE(ctx.ok());
        CHECK(ctx.error().message.find("no-such-device-xyz") != std::string::npos);
    }

    TEST_CASE("buffers share a few memory blocks, and freed space is reused") {
        auto ctx = test::open_validated_context();
        std::vector<gpu::Buffer> buffers;
        for (int i = 0; i < 200; ++i) {
            auto b = gpu::Buffer::create(*ctx, 4096 + VkDeviceSize(i) * 64, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT,
                                         gpu::MemoryUsage::device_local);
            REQUIRE(b.ok());
            buffers.push_back(std::move(b).value());
        }
        const size_t blocks = ctx->memory().block_count();
        CHECK(blocks >= 1);
        CHECK(blocks <= 2);
        const VkDeviceSize in_use = ctx->memory().bytes_in_use();
        buffers.erase(buffers.begin(), buffers.begin() + 100);
        CHECK(ctx->memory().bytes_in_use() < in_use);
        for (int i = 0; i < 100; ++i) {
            auto b = gpu::Buffer::create(*ctx, 4096, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, gpu::MemoryUsage::device_local);
            REQUIRE(b.ok());
            buffers.push_back(std::move(b).value());
        }
        CHECK(ctx->memory().block_count() == blocks);
        buffers.clear();
        CHECK(ctx->memory().bytes_in_use() == 0);
        test::require_no_validation_messages(*ctx);
    }

    TEST_CASE("an allocation larger than a block gets a block of its own, returned when freed") {
        auto ctx = test::open_validated_context();
        const size_t before = ctx->memory().block_count();
        {
            auto big = gpu::Buffer::create(*ctx, 100ull << 20, VK_BUFFER_USAGE_TRANSFER_DST_BIT, gpu::MemoryUsage::device_local);
            REQUIRE(big.ok());
            CHECK(ctx->memory().block_count() == before + 1);
        }
        CHECK(ctx->memory().block_count() == before);
        test::require_no_validation_messages(*ctx);
    }
}
