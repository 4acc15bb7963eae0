#pragma once
// A persistently mapped ring of host-visible memory for CPU-to-GPU copies. Each frame takes
// what it needs from the head; space comes back when the frame that used it has finished
// (FrameRing's completed serial), so there is never a queue-wait-idle per upload.
#include <deque>

#include "gpu/buffer.h"

namespace pbdsplat::gpu {

class UploadRing {
public:
    struct Span {
        VkBuffer buffer = VK_NULL_HANDLE;
        VkDeviceSize offset = 0;
        VkDeviceSize size = 0;
        void* ptr = nullptr;
    };

    static core::Result<UploadRing> create(Context& ctx, VkDeviceSize capacity);
    UploadRing() = default;

    // Releases the space of every frame up to and including `completed_serial`.
    void retire(uint64_t completed_serial);
    // Space for `size` bytes, owned by the frame `serial` (the one being recorded).
    core::Result<Span> allocate(uint64_t serial, VkDeviceSize size, VkDeviceSize align = 16);

    VkBuffer buffer() const { return buffer_.handle(); }
    VkDeviceSize capacity() const { return buffer_.size(); }
    VkDeviceSize in_flight_bytes() const { return used_; }

private:
    struct Mark {
        uint64_t serial;
        VkDeviceSize end;    // head after this frame's last allocation
        VkDeviceSize bytes;  // bytes this frame holds, padding of a wrap included
    };
    Buffer buffer_;
    VkDeviceSize head_ = 0;
    VkDeviceSize used_ = 0;
    std::deque<Mark> marks_;
};

} // namespace pbdsplat::gpu
