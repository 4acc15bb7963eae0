#include "gpu/stream_buffer.h"

#include <algorithm>
#include <cstring>

namespace pbdsplat::gpu {

const char* upload_path_name(UploadPath p) { return p == UploadPath::direct ? "direct" : "staged"; }

core::Result<StreamBuffer> StreamBuffer::create(Context& ctx, VkDeviceSize capacity, VkBufferUsageFlags usage,
                                                UploadPath path, uint32_t frames_in_flight) {
    if (path == UploadPath::direct && !ctx.caps().unified_memory)
        return core::make_error("direct uploads need a unified-memory device; '" + ctx.caps().name + "' is not one");
    StreamBuffer s;
    s.path_ = path;
    s.capacity_ = capacity;
    const uint32_t copies = path == UploadPath::direct ? frames_in_flight : 1;
    for (uint32_t i = 0; i < copies; ++i) {
        auto b = path == UploadPath::direct
                     ? Buffer::create(ctx, capacity, usage, MemoryUsage::direct)
                     : Buffer::create(ctx, capacity, usage | VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUsage::device_local);
        if (!b.ok()) return b.error();
        s.buffers_.push_back(std::move(b).value());
    }
    s.pending_.resize(copies);
    return s;
}

VkBuffer StreamBuffer::buffer(uint32_t slot) const {
    return path_ == UploadPath::direct ? buffers_[slot].handle() : buffers_[0].handle();
}

core::Result<VkDeviceSize> StreamBuffer::write(VkCommandBuffer cmd, uint32_t slot, uint64_t serial, UploadRing& ring,
                                               std::span<const std::byte> data, std::span<const ByteRange> ranges) {
    if (data.size() > capacity_)
        return core::make_error("stream buffer holds " + std::to_string(capacity_) + " bytes; " +
                                std::to_string(data.size()) + " were written");
    for (const ByteRange& r : ranges)
        PBDSPLAT_ASSERT(r.offset + r.size <= data.size(), "StreamBuffer::write: range beyond the data");

    if (path_ == UploadPath::direct) {
        // This slot's fence has been waited on by FrameRing::begin, so the GPU is done with it;
        // vkQueueSubmit makes host writes made before it visible to the device.
        auto* dst = static_cast<std::byte*>(buffers_[slot].mapped());
        VkDeviceSize written = 0;
        auto copy = [&](const ByteRange& r) {
            if (r.offset >= data.size()) return;  // beyond what exists now: nothing to catch up
            const VkDeviceSize n = std::min<VkDeviceSize>(r.size, data.size() - r.offset);
            std::memcpy(dst + r.offset, data.data() + r.offset, n);
            written += n;
        };
        for (const ByteRange& r : pending_[slot]) copy(r);
        pending_[slot].clear();
        for (const ByteRange& r : ranges) copy(r);
        for (uint32_t other = 0; other < pending_.size(); ++other)
            if (other != slot) pending_[other].insert(pending_[other].end(), ranges.begin(), ranges.end());
        return written;
    }

    if (ranges.empty()) return VkDeviceSize(0);
    std::vector<VkBufferCopy> copies;
    copies.reserve(ranges.size());
    for (const ByteRange& r : ranges) {
        if (r.size == 0) continue;
        auto span = ring.allocate(serial, r.size);
        if (!span.ok()) return span.error();
        std::memcpy(span->ptr, data.data() + r.offset, r.size);
        copies.push_back({span->offset, r.offset, r.size});
    }
    VkDeviceSize written = 0;
    for (const VkBufferCopy& c : copies) written += c.size;
    if (!copies.empty()) vkCmdCopyBuffer(cmd, ring.buffer(), buffers_[0].handle(), uint32_t(copies.size()), copies.data());
    return written;
}

} // namespace pbdsplat::gpu
