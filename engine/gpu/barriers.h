#pragma once
// Synchronization2 barrier helpers. Passes say which stage and access came before and which
// comes after; these turn that into one vkCmdPipelineBarrier2 each.
#include "gpu/vk.h"

namespace pbdsplat::gpu {

struct Access {
    VkPipelineStageFlags2 stage = VK_PIPELINE_STAGE_2_NONE;
    VkAccessFlags2 access = VK_ACCESS_2_NONE;
};

void buffer_barrier(VkCommandBuffer cmd, VkBuffer buffer, Access before, Access after,
                    VkDeviceSize offset = 0, VkDeviceSize size = VK_WHOLE_SIZE);

// Orders all memory accesses of `before` against `after` (e.g. one compute dispatch feeding
// the next), for work inside a pass whose steps the frame graph does not see.
void memory_barrier(VkCommandBuffer cmd, Access before, Access after);

void image_barrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, Access before,
                   VkImageLayout old_layout, Access after, VkImageLayout new_layout);

} // namespace pbdsplat::gpu
