#include "gpu/gpu_timer.h"

namespace pbdsplat::gpu {

core::Result<GpuTimer> GpuTimer::create(const Context& ctx, uint32_t max_marks) {
    GpuTimer t;
    if (!ctx.caps().timestamps) return t;  // disabled: marks are no-ops, read() returns nothing
    VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    info.queryType = VK_QUERY_TYPE_TIMESTAMP;
    info.queryCount = max_marks;
    VkQueryPool pool = VK_NULL_HANDLE;
    PBDSPLAT_VK_TRY(vkCreateQueryPool(ctx.vk(), &info, nullptr, &pool));
    t.pool_ = QueryPool(ctx.vk(), pool);
    t.capacity_ = max_marks;
    t.period_ns_ = ctx.caps().timestamp_period_ns;
    return t;
}

void GpuTimer::begin(VkCommandBuffer cmd) {
    used_ = 0;
    labels_.clear();
    if (pool_) vkCmdResetQueryPool(cmd, pool_.get(), 0, capacity_);
}

void GpuTimer::mark(VkCommandBuffer cmd, const char* label, VkPipelineStageFlags2 stage) {
    if (!pool_) return;
    PBDSPLAT_ASSERT(used_ < capacity_, "GpuTimer: more marks than the pool holds; raise max_marks");
    vkCmdWriteTimestamp2(cmd, stage, pool_.get(), used_++);
    labels_.emplace_back(label);
}

core::Result<std::vector<std::pair<std::string, double>>> GpuTimer::read(VkDevice device) const {
    std::vector<std::pair<std::string, double>> out;
    if (!pool_ || used_ < 2) return out;
    std::vector<uint64_t> ticks(used_);
    PBDSPLAT_VK_TRY(vkGetQueryPoolResults(device, pool_.get(), 0, used_, ticks.size() * sizeof(uint64_t), ticks.data(),
                                          sizeof(uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
    for (uint32_t i = 1; i < used_; ++i)
        out.emplace_back(labels_[i], double(ticks[i] - ticks[i - 1]) * double(period_ns_) * 1e-6);
    return out;
}

} // namespace pbdsplat::gpu
