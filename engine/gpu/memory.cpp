#include "gpu/memory.h"

#include <algorithm>
#include <string>

namespace pbdsplat::gpu {

MemoryAllocator::MemoryAllocator(VkDevice device, const VkPhysicalDeviceMemoryProperties& props,
                                 VkDeviceSize granularity, VkDeviceSize block_size)
    : device_(device), props_(props), granularity_(std::max<VkDeviceSize>(granularity, 1)), block_size_(block_size) {}

MemoryAllocator::~MemoryAllocator() {
    for (Block& b : blocks_) {
        if (b.memory == VK_NULL_HANDLE) continue;
        if (b.mapped) vkUnmapMemory(device_, b.memory);
        vkFreeMemory(device_, b.memory, nullptr);
    }
}

int MemoryAllocator::choose_type(uint32_t type_bits, MemoryUsage usage) const {
    constexpr VkMemoryPropertyFlags DL = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
    constexpr VkMemoryPropertyFlags HV = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT;
    constexpr VkMemoryPropertyFlags HC = VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    constexpr VkMemoryPropertyFlags CACHED = VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
    VkMemoryPropertyFlags required = 0, preferred = 0, avoided = 0;
    switch (usage) {
        case MemoryUsage::device_local: preferred = DL; break;
        case MemoryUsage::upload: required = HV | HC; avoided = CACHED; break;
        case MemoryUsage::readback: required = HV | HC; preferred = CACHED; break;
        case MemoryUsage::direct: required = DL | HV | HC; break;
    }
    int best = -1, best_score = -1;
    for (uint32_t i = 0; i < props_.memoryTypeCount; ++i) {
        if (!(type_bits & (1u << i))) continue;
        const VkMemoryPropertyFlags f = props_.memoryTypes[i].propertyFlags;
        if ((f & required) != required) continue;
        const int score = ((f & preferred) == preferred ? 2 : 0) + ((f & avoided) ? 0 : 1);
        if (score > best_score) best = int(i), best_score = score;
    }
    return best;
}

core::Result<uint32_t> MemoryAllocator::new_block(uint32_t type, VkDeviceSize size) {
    Block b;
    b.size = size;
    b.type = type;
    VkMemoryAllocateInfo info{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    info.allocationSize = size;
    info.memoryTypeIndex = type;
    PBDSPLAT_VK_TRY(vkAllocateMemory(device_, &info, nullptr, &b.memory));
    if (props_.memoryTypes[type].propertyFlags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) {
        const VkResult r = vkMapMemory(device_, b.memory, 0, VK_WHOLE_SIZE, 0, &b.mapped);
        if (r != VK_SUCCESS) {
            vkFreeMemory(device_, b.memory, nullptr);
            return vk_error("vkMapMemory", r);
        }
    }
    b.free_ranges[0] = size;
    // Reuse a slot left by a released dedicated block before growing the list.
    for (uint32_t i = 0; i < blocks_.size(); ++i)
        if (blocks_[i].memory == VK_NULL_HANDLE) {
            blocks_[i] = std::move(b);
            return i;
        }
    blocks_.push_back(std::move(b));
    return uint32_t(blocks_.size() - 1);
}

bool MemoryAllocator::carve(Block& b, VkDeviceSize size, VkDeviceSize align, VkDeviceSize& out_offset) {
    for (auto it = b.free_ranges.begin(); it != b.free_ranges.end(); ++it) {
        const VkDeviceSize start = it->first, len = it->second;
        const VkDeviceSize aligned = (start + align - 1) / align * align;
        if (aligned + size > start + len) continue;
        b.free_ranges.erase(it);
        if (aligned > start) b.free_ranges[start] = aligned - start;
        if (aligned + size < start + len) b.free_ranges[aligned + size] = start + len - (aligned + size);
        out_offset = aligned;
        return true;
    }
    return false;
}

core::Result<Allocation> MemoryAllocator::allocate(const VkMemoryRequirements& req, MemoryUsage usage) {
    const int type = choose_type(req.memoryTypeBits, usage);
    if (type < 0) return core::make_error("no Vulkan memory type fits this resource's usage");
    // Aligning everything to bufferImageGranularity keeps linear and optimal resources that
    // share a block from aliasing pages, whatever their neighbours are.
    const VkDeviceSize align = std::max(req.alignment, granularity_);
    const VkDeviceSize size = (req.size + align - 1) / align * align;

    Allocation a;
    for (uint32_t i = 0; i < blocks_.size(); ++i) {
        Block& b = blocks_[i];
        if (b.memory == VK_NULL_HANDLE || b.type != uint32_t(type)) continue;
        if (carve(b, size, align, a.offset)) {
            a.block = i;
            break;
        }
    }
    if (a.block == UINT32_MAX) {
        auto block = new_block(uint32_t(type), std::max(block_size_, size));
        if (!block.ok()) return block.error();
        a.block = block.value();
        const bool carved = carve(blocks_[a.block], size, align, a.offset);
        PBDSPLAT_ASSERT(carved, "a fresh memory block must fit the request it was sized for");
    }
    const Block& b = blocks_[a.block];
    a.memory = b.memory;
    a.size = size;
    a.mapped = b.mapped ? static_cast<char*>(b.mapped) + a.offset : nullptr;
    in_use_ += size;
    return a;
}

void MemoryAllocator::free(const Allocation& a) {
    if (a.block == UINT32_MAX) return;
    PBDSPLAT_ASSERT(a.block < blocks_.size() && blocks_[a.block].memory == a.memory,
                    "freeing an allocation that this allocator did not make (or freeing it twice)");
    Block& b = blocks_[a.block];
    in_use_ -= a.size;
    auto [it, inserted] = b.free_ranges.emplace(a.offset, a.size);
    PBDSPLAT_ASSERT(inserted, "double free of GPU memory");
    // Coalesce with the following and preceding free ranges.
    auto next = std::next(it);
    if (next != b.free_ranges.end() && it->first + it->second == next->first) {
        it->second += next->second;
        b.free_ranges.erase(next);
    }
    if (it != b.free_ranges.begin()) {
        auto prev = std::prev(it);
        if (prev->first + prev->second == it->first) {
            prev->second += it->second;
            b.free_ranges.erase(it);
        }
    }
    // Oversized (dedicated-size) blocks go back to the driver once empty; standard blocks stay for reuse.
    if (b.size > block_size_ && b.free_ranges.size() == 1 && b.free_ranges.begin()->second == b.size) {
        if (b.mapped) vkUnmapMemory(device_, b.memory);
        vkFreeMemory(device_, b.memory, nullptr);
        b = Block{};
    }
}

size_t MemoryAllocator::block_count() const {
    return size_t(std::count_if(blocks_.begin(), blocks_.end(), [](const Block& b) { return b.memory != VK_NULL_HANDLE; }));
}

} // namespace pbdsplat::gpu
