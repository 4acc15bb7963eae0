#include "gpu/buffer.h"

#include <utility>

namespace pbdsplat::gpu {

core::Result<Buffer> Buffer::create(Context& ctx, VkDeviceSize size, VkBufferUsageFlags usage, MemoryUsage memory) {
    PBDSPLAT_ASSERT(size > 0, "Buffer::create: size must be positive");
    Buffer b;
    b.ctx_ = &ctx;
    b.size_ = size;
    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = size;
    info.usage = usage;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    PBDSPLAT_VK_TRY(vkCreateBuffer(ctx.vk(), &info, nullptr, &b.buffer_));
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(ctx.vk(), b.buffer_, &req);
    auto alloc = ctx.memory().allocate(req, memory);
    if (!alloc.ok()) return alloc.error();
    b.allocation_ = alloc.value();
    PBDSPLAT_VK_TRY(vkBindBufferMemory(ctx.vk(), b.buffer_, b.allocation_.memory, b.allocation_.offset));
    return b;
}

Buffer& Buffer::operator=(Buffer&& o) noexcept {
    if (this != &o) {
        reset();
        ctx_ = std::exchange(o.ctx_, nullptr);
        buffer_ = std::exchange(o.buffer_, VK_NULL_HANDLE);
        size_ = std::exchange(o.size_, 0);
        allocation_ = std::exchange(o.allocation_, Allocation{});
    }
    return *this;
}

void Buffer::reset() {
    if (!ctx_) return;
    if (buffer_ != VK_NULL_HANDLE) vkDestroyBuffer(ctx_->vk(), buffer_, nullptr);
    ctx_->memory().free(allocation_);
    buffer_ = VK_NULL_HANDLE;
    allocation_ = {};
    ctx_ = nullptr;
}

} // namespace pbdsplat::gpu
