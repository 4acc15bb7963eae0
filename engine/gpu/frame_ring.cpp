#include "gpu/frame_ring.h"

namespace pbdsplat::gpu {

core::Result<FrameRing> FrameRing::create(Context& ctx, uint32_t frames_in_flight) {
    PBDSPLAT_ASSERT(frames_in_flight >= 1 && frames_in_flight <= 4, "FrameRing: use 1 to 4 frames in flight");
    FrameRing ring;
    ring.ctx_ = &ctx;
    ring.slots_.resize(frames_in_flight);
    for (Slot& s : ring.slots_) {
        VkCommandPoolCreateInfo pool{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
        pool.flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT;
        pool.queueFamilyIndex = ctx.device().queue_family();
        VkCommandPool p = VK_NULL_HANDLE;
        PBDSPLAT_VK_TRY(vkCreateCommandPool(ctx.vk(), &pool, nullptr, &p));
        s.pool = CommandPool(ctx.vk(), p);
        VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
        alloc.commandPool = p;
        alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        alloc.commandBufferCount = 1;
        PBDSPLAT_VK_TRY(vkAllocateCommandBuffers(ctx.vk(), &alloc, &s.cmd));
        VkFenceCreateInfo fence{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        VkFence f = VK_NULL_HANDLE;
        PBDSPLAT_VK_TRY(vkCreateFence(ctx.vk(), &fence, nullptr, &f));
        s.fence = Fence(ctx.vk(), f);
    }
    return ring;
}

FrameRing::~FrameRing() {
    if (ctx_) (void)wait_all();
}

core::Status FrameRing::wait_slot(Slot& s) {
    if (s.serial != 0) {
        const VkFence fence = s.fence.get();
        PBDSPLAT_VK_TRY(vkWaitForFences(ctx_->vk(), 1, &fence, VK_TRUE, UINT64_MAX));
        PBDSPLAT_VK_TRY(vkResetFences(ctx_->vk(), 1, &fence));
        completed_ = std::max(completed_, s.serial);
        s.serial = 0;
    }
    for (auto& destroy : s.retired) destroy();
    s.retired.clear();
    return core::Status::success();
}

core::Result<VkCommandBuffer> FrameRing::begin() {
    PBDSPLAT_ASSERT(!recording_, "FrameRing::begin called twice without submit");
    Slot& s = slots_[slot_];
    PBDSPLAT_TRY(wait_slot(s));
    PBDSPLAT_VK_TRY(vkResetCommandPool(ctx_->vk(), s.pool.get(), 0));
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    PBDSPLAT_VK_TRY(vkBeginCommandBuffer(s.cmd, &begin));
    ++serial_;
    recording_ = true;
    return s.cmd;
}

core::Status FrameRing::submit(const VkSemaphoreSubmitInfo* wait, const VkSemaphoreSubmitInfo* signal) {
    PBDSPLAT_ASSERT(recording_, "FrameRing::submit without begin");
    Slot& s = slots_[slot_];
    PBDSPLAT_VK_TRY(vkEndCommandBuffer(s.cmd));
    VkCommandBufferSubmitInfo cmd{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
    cmd.commandBuffer = s.cmd;
    VkSubmitInfo2 submit{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
    submit.commandBufferInfoCount = 1;
    submit.pCommandBufferInfos = &cmd;
    submit.waitSemaphoreInfoCount = wait ? 1u : 0u;
    submit.pWaitSemaphoreInfos = wait;
    submit.signalSemaphoreInfoCount = signal ? 1u : 0u;
    submit.pSignalSemaphoreInfos = signal;
    PBDSPLAT_VK_TRY(vkQueueSubmit2(ctx_->device().queue(), 1, &submit, s.fence.get()));
    s.serial = serial_;
    recording_ = false;
    slot_ = (slot_ + 1) % uint32_t(slots_.size());
    return core::Status::success();
}

core::Status FrameRing::wait_all() {
    PBDSPLAT_ASSERT(!recording_, "FrameRing::wait_all while a frame is being recorded; submit it first");
    for (Slot& s : slots_) PBDSPLAT_TRY(wait_slot(s));
    return core::Status::success();
}

void FrameRing::retire(std::function<void()> destroy) {
    // While recording, the object may be used by this frame; otherwise by the last submitted one.
    const uint32_t n = uint32_t(slots_.size());
    const uint32_t target = recording_ ? slot_ : (slot_ + n - 1) % n;
    slots_[target].retired.push_back(std::move(destroy));
}

} // namespace pbdsplat::gpu
