#pragma once
// A VkBuffer with its sub-allocated memory; move-only.
#include "gpu/context.h"

namespace pbdsplat::gpu {

class Buffer {
public:
    Buffer() = default;
    static core::Result<Buffer> create(Context& ctx, VkDeviceSize size, VkBufferUsageFlags usage, MemoryUsage memory);
    Buffer(Buffer&& o) noexcept { *this = std::move(o); }
    Buffer& operator=(Buffer&& o) noexcept;
    Buffer(const Buffer&) = delete;
    Buffer& operator=(const Buffer&) = delete;
    ~Buffer() { reset(); }
    void reset();

    VkBuffer handle() const { return buffer_; }
    VkDeviceSize size() const { return size_; }
    void* mapped() const { return allocation_.mapped; }  // null unless host-visible
    explicit operator bool() const { return buffer_ != VK_NULL_HANDLE; }

private:
    Context* ctx_ = nullptr;
    VkBuffer buffer_ = VK_NULL_HANDLE;
    VkDeviceSize size_ = 0;
    Allocation allocation_;
};

} // namespace pbdsplat::gpu
