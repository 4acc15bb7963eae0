#include "render/gpu_sort.h"

#include "gpu/barriers.h"
#include "gpu/descriptor_pool.h"
#include "gpu/pipeline.h"
#include "splat/gaussian_record.h"

namespace pbdsplat::render {

namespace {
constexpr uint32_t k_tile = 128 * 8;  // SORT_TILE in sort_common.glsl
constexpr uint32_t k_bins = 16;       // SORT_BINS
constexpr uint32_t k_binding_count = 6;

uint32_t tiles_for(uint32_t n) { return std::max<uint32_t>(1, (n + k_tile - 1) / k_tile); }

const gpu::Access k_compute_rw{VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                               VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT};

Vec4f normalised_plane(const Vec4f& p) { return p / p.head<3>().norm(); }
} // namespace

SplatOrder preferred_sort(const gpu::DeviceCaps& caps) { return caps.type == "cpu" ? SplatOrder::cpu : SplatOrder::gpu; }

core::Result<GpuSort> GpuSort::create(gpu::Context& ctx, uint32_t capacity, std::span<const VkBuffer> records) {
    if (capacity == 0) return core::make_error("GpuSort: capacity must be at least 1");
    if (records.empty()) return core::make_error("GpuSort: no record buffers");
    GpuSort s;
    s.capacity_ = capacity;
    VkDescriptorSetLayoutBinding bindings[k_binding_count];
    for (uint32_t b = 0; b < k_binding_count; ++b)
        bindings[b] = {b, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
    VkDescriptorSetLayoutCreateInfo set_info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    set_info.bindingCount = k_binding_count;
    set_info.pBindings = bindings;
    VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
    PBDSPLAT_VK_TRY(vkCreateDescriptorSetLayout(ctx.vk(), &set_info, nullptr, &set_layout));
    s.set_layout_ = gpu::DescriptorSetLayout(ctx.vk(), set_layout);

    auto pipeline_layout = gpu::create_pipeline_layout(ctx, set_layout, {VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(gpu_types::SortPush)});
    if (!pipeline_layout.ok()) return pipeline_layout.error();
    s.layout_ = std::move(pipeline_layout).value();
    const VkPipelineLayout layout = s.layout_.get();
    for (auto [pipeline, name] : {std::pair{&s.cull_count_, "sort_cull_count.comp"}, {&s.compact_, "sort_compact.comp"},
                                  {&s.scan_, "sort_scan.comp"}, {&s.histogram_, "sort_histogram.comp"},
                                  {&s.scatter_, "sort_scatter.comp"}, {&s.gather_, "sort_gather.comp"}}) {
        auto p = gpu::create_compute_pipeline(ctx, name, layout);
        if (!p.ok()) return p.error();
        *pipeline = std::move(p).value();
    }

    const auto n = uint32_t(records.size());
    auto pool_made = gpu::create_descriptor_pool(ctx, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, n * k_binding_count, n);
    if (!pool_made.ok()) return pool_made.error();
    s.pool_ = std::move(pool_made).value();
    const VkDescriptorPool pool = s.pool_.get();

    for (uint32_t i = 0; i < n; ++i) {
        auto slot = create_slot(ctx, capacity, records[i], pool, set_layout);
        if (!slot.ok()) return slot.error();
        s.slots_.push_back(std::move(slot).value());
    }
    return s;
}

core::Result<GpuSort::Slot> GpuSort::create_slot(gpu::Context& ctx, uint32_t capacity, VkBuffer records, VkDescriptorPool pool,
                                                VkDescriptorSetLayout set_layout) {
    // The sorted buffer holds whole mesh-shader workgroups (the gather pads the last one).
    const VkDeviceSize padded = (VkDeviceSize(capacity) + 31) / 32 * 32;
    const VkBufferUsageFlags transfer = VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    Slot slot;
    struct Want { gpu::Buffer* buffer; VkDeviceSize bytes; VkBufferUsageFlags usage; };
    const Want wants[] = {
        {&slot.keys, 2 * VkDeviceSize(capacity) * 4, transfer},
        {&slot.values, 2 * VkDeviceSize(capacity) * 4, transfer},
        {&slot.counts, VkDeviceSize(k_bins) * tiles_for(capacity) * 4, 0},
        {&slot.control, SORT_CONTROL_WORDS * 4, VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | transfer},
        {&slot.sorted, padded * sizeof(splat::GaussianRecord), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | transfer}};
    for (const Want& w : wants) {
        auto b = gpu::Buffer::create(ctx, w.bytes, w.usage | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::MemoryUsage::device_local);
        if (!b.ok()) return b.error();
        *w.buffer = std::move(b).value();
    }
    VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    alloc.descriptorPool = pool;
    alloc.descriptorSetCount = 1;
    alloc.pSetLayouts = &set_layout;
    PBDSPLAT_VK_TRY(vkAllocateDescriptorSets(ctx.vk(), &alloc, &slot.set));
    const VkBuffer targets[k_binding_count] = {slot.keys.handle(), slot.values.handle(), records,
                                               slot.counts.handle(), slot.control.handle(), slot.sorted.handle()};
    VkDescriptorBufferInfo infos[k_binding_count];
    VkWriteDescriptorSet writes[k_binding_count];
    for (uint32_t b = 0; b < k_binding_count; ++b) {
        infos[b] = {targets[b], 0, VK_WHOLE_SIZE};
        writes[b] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        writes[b].dstSet = slot.set;
        writes[b].dstBinding = b;
        writes[b].descriptorCount = 1;
        writes[b].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        writes[b].pBufferInfo = &infos[b];
    }
    vkUpdateDescriptorSets(ctx.vk(), k_binding_count, writes, 0, nullptr);
    return slot;
}

void GpuSort::dispatch(VkCommandBuffer cmd, const gpu::Pipeline& p, uint32_t slot, const gpu_types::SortPush& push,
                       uint32_t groups) const {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p.get());
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.get(), 0, 1, &slots_[slot].set, 0, nullptr);
    vkCmdPushConstants(cmd, layout_.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
    vkCmdDispatch(cmd, groups, 1, 1);
    gpu::memory_barrier(cmd, k_compute_rw, k_compute_rw);
}

void GpuSort::radix_passes(VkCommandBuffer cmd, uint32_t slot, gpu_types::SortPush push) const {
    // Eight 4-bit digits, least significant first; an even count leaves the result in the
    // first halves, where the gather reads it.
    for (uint32_t pass = 0; pass < 8; ++pass) {
        push.shift = 4 * pass;
        push.src_offset = pass % 2 == 0 ? 0 : capacity_;
        push.dst_offset = pass % 2 == 0 ? capacity_ : 0;
        push.scan_length = k_bins * push.tiles;
        push.write_total = 0;
        dispatch(cmd, histogram_, slot, push, push.tiles);
        dispatch(cmd, scan_, slot, push, 1);
        dispatch(cmd, scatter_, slot, push, push.tiles);
    }
}

void GpuSort::record(VkCommandBuffer cmd, uint32_t slot, uint32_t count, const SortView& v) const {
    gpu_types::SortPush push{};
    const Vec4f row = v.view.row(2);
    push.depth_row = {row.x(), row.y(), row.z(), row.w()};
    // Side planes of the clip volume (-w <= x, y <= w) taken back to world space.
    const Mat4f m = v.proj * v.view;
    const Vec4f planes[4] = {normalised_plane(m.row(3) + m.row(0)), normalised_plane(m.row(3) - m.row(0)),
                             normalised_plane(m.row(3) + m.row(1)), normalised_plane(m.row(3) - m.row(1))};
    for (int k = 0; k < 4; ++k) push.planes[k] = {planes[k].x(), planes[k].y(), planes[k].z(), planes[k].w()};
    push.limits = {v.z_near, v.z_far, v.cull_radius_per_scale, 0.0f};
    push.count = std::min(count, capacity_);
    push.tiles = tiles_for(push.count);
    push.scan_length = push.tiles;
    dispatch(cmd, cull_count_, slot, push, push.tiles);
    push.write_total = 1;
    dispatch(cmd, scan_, slot, push, 1);
    push.write_total = 0;
    dispatch(cmd, compact_, slot, push, push.tiles);
    radix_passes(cmd, slot, push);
    const uint32_t padded = (push.count + SORT_MESH_GROUP - 1) / SORT_MESH_GROUP * SORT_MESH_GROUP;
    dispatch(cmd, gather_, slot, push, std::max<uint32_t>(1, (padded + 127) / 128));
}

void GpuSort::record_radix(VkCommandBuffer cmd, uint32_t slot, uint32_t count) const {
    gpu_types::SortPush push{};
    push.count = std::min(count, capacity_);
    push.tiles = tiles_for(push.count);
    radix_passes(cmd, slot, push);
}

} // namespace pbdsplat::render
