#include <doctest/doctest.h>

#include <algorithm>
#include <cstring>
#include <numeric>
#include <random>

#include <Eigen/Geometry>

#include "gpu/barriers.h"
#include "gpu/buffer.h"
#include "gpu/texture.h"
#include "render/gpu_sort.h"
#include "render/splat_renderer.h"
#include "scene/builtin_scene.h"
#include "scene/ply_view.h"
#include "passes/offscreen_renderer.h"
#include "splat/sort.h"
#include "support/gpu_fixture.h"

#include "support/skip.h"
#include "support/why.h"
using namespace pbdsplat;

namespace {

const gpu::Access k_copy_write{VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT};
const gpu::Access k_copy_read{VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT};
const gpu::Access k_compute{VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                            VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT};
const gpu::Access k_host_read{VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT};

gpu::Buffer host_buffer(gpu::Context& ctx, VkDeviceSize bytes, gpu::MemoryUsage usage, VkBufferUsageFlags flags) {
    auto b = gpu::Buffer::create(ctx, bytes, flags, usage);
    REQUIRE_MESSAGE(b.ok(), test::why(b));
    return std::move(b).value();
}

// Copies `words` 32-bit words out of `src` (after compute writes) into host memory.
std::vector<uint32_t> read_words(gpu::Context& ctx, VkBuffer src, size_t words) {
    gpu::Buffer out = host_buffer(ctx, words * 4, gpu::MemoryUsage::readback, VK_BUFFER_USAGE_TRANSFER_DST_BIT);
    REQUIRE(gpu::submit_once(ctx, [&](VkCommandBuffer cmd) {
                gpu::memory_barrier(cmd, k_compute, k_copy_read);
                const VkBufferCopy region{0, 0, words * 4};
                vkCmdCopyBuffer(cmd, src, out.handle(), 1, &region);
                gpu::memory_barrier(cmd, k_copy_write, k_host_read);
            }).ok());
    std::vector<uint32_t> v(words);
    std::memcpy(v.data(), out.mapped(), words * 4);
    return v;
}

// Runs the radix passes alone over `keys` (values: 0, 1, 2, ...) and returns the values in
// the order the GPU left them.
std::vector<uint32_t> gpu_radix(gpu::Context& ctx, const std::vector<uint32_t>& keys) {
    const auto n = uint32_t(keys.size());
    gpu::Buffer records = host_buffer(ctx, 64, gpu::MemoryUsage::upload, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    const VkBuffer record_buffer = records.handle();
    auto sort = render::GpuSort::create(ctx, n, std::span<const VkBuffer>(&record_buffer, 1));
    REQUIRE_MESSAGE(sort.ok(), test::why(sort));
    std::vector<uint32_t> values(n), control(SORT_CONTROL_WORDS, 0u);
    std::iota(values.begin(), values.end(), 0u);
    control[SORT_CONTROL_VISIBLE] = n;
    gpu::Buffer staging = host_buffer(ctx, (2 * size_t(n) + SORT_CONTROL_WORDS) * 4, gpu::MemoryUsage::upload,
                                      VK_BUFFER_USAGE_TRANSFER_SRC_BIT);
    auto* w = static_cast<uint32_t*>(staging.mapped());
    std::memcpy(w, keys.data(), n * 4);
    std::memcpy(w + n, values.data(), n * 4);
    std::memcpy(w + 2 * n, control.data(), control.size() * 4);
    REQUIRE(gpu::submit_once(ctx, [&](VkCommandBuffer cmd) {
                const VkBufferCopy k{0, 0, n * 4u}, v{n * 4u, 0, n * 4u}, c{2 * n * 4u, 0, SORT_CONTROL_WORDS * 4u};
                vkCmdCopyBuffer(cmd, staging.handle(), sort->keys(0), 1, &k);
                vkCmdCopyBuffer(cmd, staging.handle(), sort->values(0), 1, &v);
                vkCmdCopyBuffer(cmd, staging.handle(), sort->control(0), 1, &c);
                gpu::memory_barrier(cmd, k_copy_write, k_compute);
                sort->record_radix(cmd, 0, n);
            }).ok());
    return read_words(ctx, sort->values(0), n);
}

std::vector<uint32_t> stable_order(const std::vector<uint32_t>& keys) {
    std::vector<uint32_t> order(keys.size());
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return keys[a] < keys[b]; });
    return order;
}

void place(splat::GaussianRecord& r, float x, float y, float z) {
    r.position[0] = x;
    r.position[1] = y;
    r.position[2] = z;
}

render::FrameInputs sort_frame() {
    render::FrameInputs f;
    f.camera.eye = Vec3f(0.3f, 0.4f, 4.0f);
    f.style.order = render::SplatOrder::gpu;
    return f;
}

} // namespace

TEST_SUITE("render/sort") {
    TEST_CASE("the radix passes give std::stable_sort's order, equal keys included") {
        auto ctx = test::open_validated_context();
        std::mt19937 rng(7);
        // One element, one partial tile, several tiles; keys with few distinct values (many
        // ties) and keys over the whole 32-bit range.
        for (const uint32_t n : {1u, 777u, 5000u, 40000u}) {
            for (const uint32_t mask : {0x0000000Fu, 0xF00F0F00u, 0xFFFFFFFFu}) {
                std::vector<uint32_t> keys(n);
                for (uint32_t& k : keys) k = uint32_t(rng()) & mask;
                const auto gpu = gpu_radix(*ctx, keys);
                const auto cpu = stable_order(keys);
                INFO("n = " << n << ", key mask " << std::hex << mask);
                CHECK(gpu == cpu);
            }
        }
        test::require_no_validation_messages(*ctx);
    }

    TEST_CASE("cull and sort: the visible records far to near, ties in record order, as the CPU sort") {
        auto ctx = test::open_validated_context();
        // A grid in front of the camera, every position twice (exact ties), plus records
        // clearly outside the frustum (behind, beside) and with zero scale: culled.
        std::vector<splat::GaussianRecord> records;
        splat::Appearance look;
        look.scale = 0.02f;
        splat::GaussianRecord r = splat::make_record(Vec3f::Zero(), Vec3f::UnitZ(), look);
        std::vector<splat::GaussianRecord> visible;
        for (int copy = 0; copy < 2; ++copy)
            for (int i = 0; i < 30; ++i)
                for (int j = 0; j < 30; ++j) {
                    place(r, -0.6f + 0.04f * float(i), -0.6f + 0.04f * float(j), -0.5f + 0.03f * float((i * 7 + j * 3) % 31));
                    records.push_back(r);
                }
        const size_t in_view = records.size();
        for (int k = 0; k < 50; ++k) {
            place(r, 0.0f, 0.0f, 8.0f + float(k));  // behind the camera
            records.push_back(r);
            place(r, 30.0f + float(k), 0.0f, 0.0f);  // far to the right
            records.push_back(r);
        }
        look.scale = 0.0f;
        records.push_back(splat::make_record(Vec3f::Zero(), Vec3f::UnitZ(), look));
        std::shuffle(records.begin(), records.end(), std::mt19937(3));
        for (const auto& rec : records)
            if (rec.scale_half != 0 && rec.position[2] < 2.0f && rec.position[0] < 5.0f) visible.push_back(rec);
        REQUIRE(visible.size() == in_view);

        const render::FrameInputs frame = sort_frame();
        splat::SortScratch scratch;
        splat::sort_far_to_near(visible, math::look_at(frame.camera.eye, frame.camera.target, frame.camera.up), scratch);

        render::RendererOptions o;
        o.width = 64;
        o.height = 64;
        o.max_splats = uint32_t(records.size());
        o.frames_in_flight = 1;
        o.gpu_sort = true;
        auto renderer = passes::OffscreenRenderer::create(*ctx, o);
        REQUIRE_MESSAGE(renderer.ok(), test::why(renderer));
        REQUIRE(renderer.value()->render(records, frame).ok());
        REQUIRE(renderer.value()->finish().ok());
        const render::SplatRenderer& sr = renderer.value()->splat_renderer();
        const auto control = read_words(*ctx, sr.sort_control_buffer(), SORT_CONTROL_WORDS);
        CHECK(control[SORT_CONTROL_VISIBLE] == in_view);
        CHECK(control[SORT_CONTROL_DRAW] == in_view);
        CHECK(control[SORT_CONTROL_DRAW_PULL] == 6 * in_view);
        CHECK(control[SORT_CONTROL_MESH] == (in_view + SORT_MESH_GROUP - 1) / SORT_MESH_GROUP);
        const auto words = read_words(*ctx, sr.sorted_records_buffer(), in_view * sizeof(splat::GaussianRecord) / 4);
        REQUIRE(std::memcmp(words.data(), visible.data(), words.size() * 4) == 0);
        test::require_no_validation_messages(*ctx);
    }

    TEST_CASE("a capture (anisotropic, view-dependent colour of degree 3) sorted on the GPU draws what the CPU sort draws") {
        // Thousands of overlapping needles and discs on a shell, each with its own degree 1-3
        // colour: the GPU sort gathers only the records, so each splat's axes and colour must be
        // found through the sort's order, or the image scrambles.
        std::mt19937 rng(11);
        std::normal_distribution<float> gauss(0.0f, 1.0f);
        std::uniform_real_distribution<float> unit(0.0f, 1.0f);
        splat::PlyGaussians file;
        for (int i = 0; i < 3000; ++i) {
            const Vec3f d = Vec3f(gauss(rng), gauss(rng), gauss(rng)).normalized();
            const Eigen::Matrix3f turn = Eigen::Quaternionf(Eigen::Vector4f(gauss(rng), gauss(rng), gauss(rng), gauss(rng)).normalized())
                                             .toRotationMatrix();
            const Eigen::Matrix3f axes = turn * Vec3f(0.02f + 0.1f * unit(rng), 0.02f + 0.05f * unit(rng), 0.005f).asDiagonal();
            splat::Appearance a;
            a.albedo = Vec3f(unit(rng), unit(rng), unit(rng));
            a.scale = splat::shape_reach(axes);
            file.records.push_back(splat::make_record(d, d, a));
            file.shapes.push_back(splat::make_shape(axes));
            splat::GaussianSH sh{};
            for (auto& c : sh.rest_half) c = core::float_to_half(0.2f * gauss(rng));
            file.sh.push_back(sh);
        }
        file.sh_degree = 3;
        for (const render::SplatPath path : {render::SplatPath::geometry, render::SplatPath::mesh, render::SplatPath::vertex}) {
            auto ctx = test::open_validated_context();
            if (const std::string why = render::splat_path_unsupported(ctx->caps(), path); !why.empty()) {
                test::skip("path " + std::string(render::splat_path_name(path)) + ": " + why);
                continue;
            }
            auto draw = [&](bool gpu_sort) {
                splat::PlyGaussians copy = file;
                render::RendererOptions o = scene::ply_renderer_options(copy, 200, 150, gpu_sort);
                o.path = path;
                render::FrameInputs frame = scene::ply_view(copy.records);
                frame.camera.eye = Vec3f(0.4f, 0.9f, 2.6f);
                scene::order_ply(copy, frame, gpu_sort);
                auto r = passes::OffscreenRenderer::create(*ctx, o);
                REQUIRE_MESSAGE(r.ok(), test::why(r));
                REQUIRE(r.value()->render(copy.records, frame, {}, copy.shapes, copy.sh).ok());
                auto img = r.value()->finish();
                REQUIRE(img.ok());
                return std::move(img).value();
            };
            const auto cpu = draw(false), gpu = draw(true);
            // Drawn unsorted, the same splats composite in another order: the check can fail.
            auto diff = core::compare_images(cpu, gpu, 1);
            REQUIRE(diff.ok());
            MESSAGE(std::string(render::splat_path_name(path)) << ": capture, GPU against CPU sort, PSNR " << diff->psnr_db << " dB");
            CHECK(diff->share_over == 0.0);
            test::require_no_validation_messages(*ctx);
        }
    }

    TEST_CASE("GPU-sorted, CPU-sorted: the same image on every path the device has") {
        auto ctx = test::open_validated_context();
        const auto scene = scene::make_builtin_scene(4);
        for (const render::SplatPath path : {render::SplatPath::geometry, render::SplatPath::mesh, render::SplatPath::vertex}) {
            if (const std::string why = render::splat_path_unsupported(ctx->caps(), path); !why.empty()) {
                test::skip("path " + std::string(render::splat_path_name(path)) + ": " + why);
                continue;
            }
            auto draw = [&](render::SplatOrder order) {
                render::RendererOptions o;
                o.width = 160;
                o.height = 120;
                o.path = path;
                o.max_splats = uint32_t(scene.records.size());
                o.frames_in_flight = 1;
                o.gpu_sort = order == render::SplatOrder::gpu;
                render::FrameInputs frame = scene.frame;
                frame.style.order = order;
                std::vector<splat::GaussianRecord> records = scene.records;
                splat::SortScratch scratch;
                if (order == render::SplatOrder::cpu)
                    splat::sort_far_to_near(records, math::look_at(frame.camera.eye, frame.camera.target, frame.camera.up), scratch);
                auto r = passes::OffscreenRenderer::create(*ctx, o);
                REQUIRE_MESSAGE(r.ok(), test::why(r));
                REQUIRE(r.value()->render(records, frame).ok());
                auto img = r.value()->finish();
                REQUIRE(img.ok());
                return std::move(img).value();
            };
            const auto cpu = draw(render::SplatOrder::cpu), gpu = draw(render::SplatOrder::gpu);
            auto diff = core::compare_images(cpu, gpu, 1);
            REQUIRE(diff.ok());
            MESSAGE(std::string(render::splat_path_name(path)) << ": GPU against CPU sort, PSNR " << diff->psnr_db << " dB");
            CHECK(diff->share_over == 0.0);
        }
        test::require_no_validation_messages(*ctx);
    }
}
