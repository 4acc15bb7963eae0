#include "gpu/upload_ring.h"

namespace pbdsplat::gpu {

core::Result<UploadRing> UploadRing::create(Context& ctx, VkDeviceSize capacity) {
    UploadRing ring;
    auto buffer = Buffer::create(ctx, capacity, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUsage::upload);
    if (!buffer.ok()) return buffer.error();
    ring.buffer_ = std::move(buffer).value();
    PBDSPLAT_ASSERT(ring.buffer_.mapped(), "upload memory must be host-visible");
    return ring;
}

void UploadRing::retire(uint64_t completed_serial) {
    while (!marks_.empty() && marks_.front().serial <= completed_serial) {
        used_ -= marks_.front().bytes;
        marks_.pop_front();
    }
    if (marks_.empty()) head_ = 0, used_ = 0;  // everything is free: start over at the front
}

core::Result<UploadRing::Span> UploadRing::allocate(uint64_t serial, VkDeviceSize size, VkDeviceSize align) {
    const VkDeviceSize cap = buffer_.size();
    if (size > cap)
        return core::make_error("upload of " + std::to_string(size) + " bytes exceeds the staging ring's " +
                                std::to_string(cap) + " bytes; create the renderer with a larger upload ring");
    VkDeviceSize start = (head_ + align - 1) / align * align;
    VkDeviceSize taken = start - head_;
    if (start + size > cap) {  // wrap: the tail end of the buffer is lost to this frame
        taken = (cap - head_);
        start = 0;
    }
    taken += size;
    if (used_ + taken > cap)
        return core::make_error("the staging ring is full: the GPU is " + std::to_string(marks_.size()) +
                                " frames behind; enlarge the ring or wait for a frame to finish");
    head_ = start + size;
    used_ += taken;
    if (marks_.empty() || marks_.back().serial != serial) marks_.push_back({serial, head_, 0});
    marks_.back().end = head_;
    marks_.back().bytes += taken;
    return Span{buffer_.handle(), start, size, static_cast<char*>(buffer_.mapped()) + start};
}

} // namespace pbdsplat::gpu
