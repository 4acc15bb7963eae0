#include "gpu/pipeline_counter.h"

#include <array>
#include <vector>

#include "core/assert.h"

namespace pbdsplat::gpu {

namespace {
// The order of the results follows the bits' order.
constexpr VkQueryPipelineStatisticFlags k_counted =
    VK_QUERY_PIPELINE_STATISTIC_CLIPPING_INVOCATIONS_BIT | VK_QUERY_PIPELINE_STATISTIC_FRAGMENT_SHADER_INVOCATIONS_BIT;
} // namespace

core::Result<PipelineCounter> PipelineCounter::create(const Context& ctx, uint32_t max_spans) {
    PipelineCounter c;
    if (!ctx.caps().pipeline_statistics) return c;
    VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    info.queryType = VK_QUERY_TYPE_PIPELINE_STATISTICS;
    info.queryCount = max_spans;
    info.pipelineStatistics = k_counted;
    VkQueryPool pool = VK_NULL_HANDLE;
    PBDSPLAT_VK_TRY(vkCreateQueryPool(ctx.vk(), &info, nullptr, &pool));
    c.pool_ = QueryPool(ctx.vk(), pool);
    c.capacity_ = max_spans;
    return c;
}

void PipelineCounter::reset(VkCommandBuffer cmd) {
    used_ = 0;
    open_ = false;
    if (pool_) vkCmdResetQueryPool(cmd, pool_.get(), 0, capacity_);
}

void PipelineCounter::begin(VkCommandBuffer cmd) {
    if (!pool_) return;
    PBDSPLAT_ASSERT(!open_ && used_ < capacity_, "PipelineCounter: a span begun inside another, or more spans than the pool holds");
    vkCmdBeginQuery(cmd, pool_.get(), used_, 0);
    open_ = true;
}

void PipelineCounter::end(VkCommandBuffer cmd) {
    if (!pool_) return;
    PBDSPLAT_ASSERT(open_, "PipelineCounter: end() without begin()");
    vkCmdEndQuery(cmd, pool_.get(), used_++);
    open_ = false;
}

core::Result<PipelineCounts> PipelineCounter::read(VkDevice device) const {
    PipelineCounts sum;
    if (!pool_ || used_ == 0) return sum;
    std::vector<std::array<uint64_t, 2>> spans(used_);
    PBDSPLAT_VK_TRY(vkGetQueryPoolResults(device, pool_.get(), 0, used_, spans.size() * sizeof(spans[0]), spans.data(), sizeof(spans[0]),
                                          VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
    for (const auto& s : spans) sum += PipelineCounts{s[0], s[1]};
    return sum;
}

} // namespace pbdsplat::gpu
