#pragma once
// Far-to-near order on the GPU (paper section 5.4): cull the splats outside the view frustum,
// pack the visible ones in record order, radix-sort their 32-bit depth keys (eight stable
// 4-bit passes, no subgroup operations), and gather the records in that order together with
// the indirect draw arguments of every splat path. Equal depths keep their record order, so
// the result is what std::stable_sort gives on the CPU.
//
// The kernels' dependencies on one another are internal barriers; the frame graph sees one
// pass that reads the records and writes the sorted records and the draw arguments.
#include <span>
#include <vector>

#include "gpu/buffer.h"
#include "gpu/device_handle.h"
#include "render/frame_inputs.h"

namespace pbdsplat::render {

// What culling needs from the frame.
struct SortView {
    Mat4f view = Mat4f::Identity();  // world -> view (looking down -z)
    Mat4f proj = Mat4f::Identity();  // view -> clip, Vulkan conventions
    float z_near = 0.05f, z_far = 100.0f;
    float cull_radius_per_scale = 3.0f;  // kappa times the global scale multiplier
};

class GpuSort {
public:
    // `records[i]` is the record buffer of frame slot i (one set of sort buffers per slot).
    static core::Result<GpuSort> create(gpu::Context& ctx, uint32_t capacity, std::span<const VkBuffer> records);
    GpuSort() = default;

    // The whole sort for `count` records of slot `slot`.
    void record(VkCommandBuffer cmd, uint32_t slot, uint32_t count, const SortView& view) const;
    // Only the radix passes, over the `count` keys and values already in the first halves of
    // keys(slot) and values(slot), with control(slot)[SORT_CONTROL_VISIBLE] = count: for tests.
    void record_radix(VkCommandBuffer cmd, uint32_t slot, uint32_t count) const;

    uint32_t capacity() const { return capacity_; }
    VkBuffer sorted_records(uint32_t slot) const { return slots_[slot].sorted.handle(); }
    VkBuffer control(uint32_t slot) const { return slots_[slot].control.handle(); }
    VkBuffer keys(uint32_t slot) const { return slots_[slot].keys.handle(); }
    VkBuffer values(uint32_t slot) const { return slots_[slot].values.handle(); }

private:
    struct Slot {
        gpu::Buffer keys, values, counts, control, sorted;
        VkDescriptorSet set = VK_NULL_HANDLE;
    };
    // One frame's buffers and descriptor set over `records`.
    static core::Result<Slot> create_slot(gpu::Context& ctx, uint32_t capacity, VkBuffer records, VkDescriptorPool pool,
                                          VkDescriptorSetLayout set_layout);
    void dispatch(VkCommandBuffer cmd, const gpu::Pipeline& p, uint32_t slot, const gpu_types::SortPush& push,
                  uint32_t groups) const;
    void radix_passes(VkCommandBuffer cmd, uint32_t slot, gpu_types::SortPush push) const;

    uint32_t capacity_ = 0;
    gpu::DescriptorSetLayout set_layout_;
    gpu::DescriptorPool pool_;
    gpu::PipelineLayout layout_;
    gpu::Pipeline cull_count_, compact_, scan_, histogram_, scatter_, gather_;
    std::vector<Slot> slots_;
};

// Which sort a frame graph should run on this device when the scene leaves it open: the CPU's
// stable sort on CPU devices (Lavapipe: a compute dispatch there runs on the same cores, with
// more passes), the GPU's everywhere else.
SplatOrder preferred_sort(const gpu::DeviceCaps& caps);

} // namespace pbdsplat::render
