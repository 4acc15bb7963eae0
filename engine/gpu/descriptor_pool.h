#pragma once
// A descriptor pool for `sets` sets holding `descriptors` descriptors of one type in all: the
// shape of every pool here.
#include "gpu/context.h"
#include "gpu/device_handle.h"

namespace pbdsplat::gpu {

core::Result<DescriptorPool> create_descriptor_pool(const Context& ctx, VkDescriptorType type, uint32_t descriptors, uint32_t sets);

} // namespace pbdsplat::gpu
