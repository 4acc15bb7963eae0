#pragma once
// The Vulkan C API, and how a failed call becomes a core::Error.
#include <vulkan/vulkan.h>

#include "core/result.h"

namespace pbdsplat::gpu {

const char* vk_result_name(VkResult r);

// "vkCreateDevice failed: VK_ERROR_INITIALIZATION_FAILED".
core::Error vk_error(const char* call, VkResult r);

} // namespace pbdsplat::gpu

// Returns a core::Error from the enclosing function when a Vulkan call fails.
#define PBDSPLAT_VK_TRY(call)                                              \
    do {                                                                   \
        const VkResult pbdsplat_vk_r_ = (call);                            \
        if (pbdsplat_vk_r_ != VK_SUCCESS)                                  \
            return ::pbdsplat::gpu::vk_error(#call, pbdsplat_vk_r_);       \
    } while (0)
