#pragma once
// GPU memory sub-allocated from a few large blocks per memory type: one vkAllocateMemory per
// buffer is slow, runs into maxMemoryAllocationCount, and the validation layer's best-practices
// check warns about it. Host-visible blocks stay mapped for their whole life.
#include <cstdint>
#include <map>
#include <memory>
#include <vector>

#include "gpu/vk.h"

namespace pbdsplat::gpu {

enum class MemoryUsage {
    device_local,  // GPU-only data (render targets, device buffers)
    upload,        // CPU writes, GPU reads: staging ring, uniforms
    readback,      // GPU writes, CPU reads
    direct,        // device-local and CPU-writable (unified-memory devices only)
};

class MemoryAllocator;

struct Allocation {
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkDeviceSize offset = 0;
    VkDeviceSize size = 0;
    void* mapped = nullptr;  // non-null for host-visible memory
    uint32_t block = UINT32_MAX;
};

class MemoryAllocator {
public:
    MemoryAllocator(VkDevice device, const VkPhysicalDeviceMemoryProperties& props, VkDeviceSize granularity,
                    VkDeviceSize block_size = 64ull << 20);
    ~MemoryAllocator();
    MemoryAllocator(const MemoryAllocator&) = delete;
    MemoryAllocator& operator=(const MemoryAllocator&) = delete;

    core::Result<Allocation> allocate(const VkMemoryRequirements& req, MemoryUsage usage);
    void free(const Allocation& a);

    // Index of the memory type chosen for `usage` among `type_bits`, or -1.
    int choose_type(uint32_t type_bits, MemoryUsage usage) const;

    size_t block_count() const;
    VkDeviceSize bytes_in_use() const { return in_use_; }

private:
    struct Block {
        VkDeviceMemory memory = VK_NULL_HANDLE;
        VkDeviceSize size = 0;
        uint32_t type = 0;
        void* mapped = nullptr;
        std::map<VkDeviceSize, VkDeviceSize> free_ranges;  // offset -> size, coalesced
    };
    core::Result<uint32_t> new_block(uint32_t type, VkDeviceSize size);
    static bool carve(Block& b, VkDeviceSize size, VkDeviceSize align, VkDeviceSize& out_offset);

    VkDevice device_;
    VkPhysicalDeviceMemoryProperties props_;
    VkDeviceSize granularity_;
    VkDeviceSize block_size_;
    std::vector<Block> blocks_;
    VkDeviceSize in_use_ = 0;
};

} // namespace pbdsplat::gpu
