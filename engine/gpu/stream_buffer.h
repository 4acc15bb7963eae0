#pragma once
// A GPU buffer the CPU rewrites every frame (the Gaussian records). Two paths:
//  - staged: one device-local buffer; the changed ranges go through the UploadRing and a copy
//    recorded in the frame's command buffer, fenced by barriers;
//  - direct: on unified-memory devices (Lavapipe) the copy is pure overhead, so each frame in
//    flight has its own host-visible device buffer, written in place.
#include <span>
#include <vector>

#include "gpu/barriers.h"
#include "gpu/upload_ring.h"

namespace pbdsplat::gpu {

enum class UploadPath { staged, direct };
const char* upload_path_name(UploadPath p);

struct ByteRange {
    VkDeviceSize offset = 0;
    VkDeviceSize size = 0;
};

class StreamBuffer {
public:
    static core::Result<StreamBuffer> create(Context& ctx, VkDeviceSize capacity, VkBufferUsageFlags usage,
                                             UploadPath path, uint32_t frames_in_flight);
    StreamBuffer() = default;

    UploadPath path() const { return path_; }
    VkDeviceSize capacity() const { return capacity_; }

    // Writes the given ranges of `data` (the whole contents, `data.size()` bytes) for the frame in
    // slot `slot`; `ranges` are what changed since the previous frame. Staged writes record
    // copies into `cmd` (the frame graph places the barriers around them: `staged_use`). Direct
    // writes also replay the ranges other frames changed since this slot's buffer was last
    // written. Returns the bytes written.
    core::Result<VkDeviceSize> write(VkCommandBuffer cmd, uint32_t slot, uint64_t serial, UploadRing& ring,
                                     std::span<const std::byte> data, std::span<const ByteRange> ranges);
    // How a staged write uses the device buffer.
    static constexpr Access staged_use{VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT};

    // The buffer the frame in `slot` reads.
    VkBuffer buffer(uint32_t slot) const;

private:
    UploadPath path_ = UploadPath::staged;
    VkDeviceSize capacity_ = 0;
    std::vector<Buffer> buffers_;  // one (staged) or one per frame in flight (direct)
    std::vector<std::vector<ByteRange>> pending_;  // direct: ranges each slot has yet to catch up on
};

} // namespace pbdsplat::gpu
