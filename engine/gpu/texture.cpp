#include "gpu/texture.h"

#include <cstddef>
#include <cstring>
#include <vector>

#include "core/half.h"
#include "gpu/barriers.h"
#include "gpu/buffer.h"

namespace pbdsplat::gpu {

core::Status submit_once(Context& ctx, const std::function<void(VkCommandBuffer)>& record) {
    VkCommandPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pool_info.flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT;
    pool_info.queueFamilyIndex = ctx.device().queue_family();
    VkCommandPool p = VK_NULL_HANDLE;
    PBDSPLAT_VK_TRY(vkCreateCommandPool(ctx.vk(), &pool_info, nullptr, &p));
    const CommandPool pool(ctx.vk(), p);
    VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    alloc.commandPool = p;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    PBDSPLAT_VK_TRY(vkAllocateCommandBuffers(ctx.vk(), &alloc, &cmd));
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    PBDSPLAT_VK_TRY(vkBeginCommandBuffer(cmd, &begin));
    record(cmd);
    PBDSPLAT_VK_TRY(vkEndCommandBuffer(cmd));
    VkFenceCreateInfo fence_info{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VkFence f = VK_NULL_HANDLE;
    PBDSPLAT_VK_TRY(vkCreateFence(ctx.vk(), &fence_info, nullptr, &f));
    const Fence fence(ctx.vk(), f);
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cmd;
    PBDSPLAT_VK_TRY(vkQueueSubmit(ctx.device().queue(), 1, &submit, f));
    PBDSPLAT_VK_TRY(vkWaitForFences(ctx.vk(), 1, &f, VK_TRUE, UINT64_MAX));
    return core::Status::success();
}

core::Result<Texture> Texture::create_rgba16f(Context& ctx, uint32_t width, uint32_t height, std::span<const float> texels) {
    if (width == 0 || height == 0 || texels.size() != size_t(width) * height * 4)
        return core::make_error("texture: need width * height RGBA texels");
    std::vector<uint16_t> half(texels.size());
    for (size_t i = 0; i < texels.size(); ++i) half[i] = core::float_to_half(texels[i]);
    return create(ctx, width, height, VK_FORMAT_R16G16B16A16_SFLOAT, std::as_bytes(std::span<const uint16_t>(half)),
                  VK_SAMPLER_ADDRESS_MODE_REPEAT, VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE);
}

core::Result<Texture> Texture::create_rgba8_srgb(Context& ctx, uint32_t width, uint32_t height, std::span<const uint8_t> texels,
                                                VkSamplerAddressMode wrap_u, VkSamplerAddressMode wrap_v) {
    if (width == 0 || height == 0 || texels.size() != size_t(width) * height * 4)
        return core::make_error("texture: need width * height RGBA texels");
    return create(ctx, width, height, VK_FORMAT_R8G8B8A8_SRGB, std::as_bytes(texels), wrap_u, wrap_v);
}

core::Result<Texture> Texture::create(Context& ctx, uint32_t width, uint32_t height, VkFormat format, std::span<const std::byte> bytes,
                                      VkSamplerAddressMode wrap_u, VkSamplerAddressMode wrap_v) {
    Texture t;
    auto image = Image::create_2d(ctx, width, height, format, VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                                  VK_IMAGE_ASPECT_COLOR_BIT);
    if (!image.ok()) return image.error();
    t.image_ = std::move(image).value();
    auto staging = Buffer::create(ctx, bytes.size(), VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUsage::upload);
    if (!staging.ok()) return staging.error();
    std::memcpy(staging->mapped(), bytes.data(), bytes.size());
    const VkImage img = t.image_.handle();
    const VkBuffer src = staging->handle();
    PBDSPLAT_TRY(submit_once(ctx, [&](VkCommandBuffer cmd) {
        image_barrier(cmd, img, VK_IMAGE_ASPECT_COLOR_BIT, {}, VK_IMAGE_LAYOUT_UNDEFINED,
                      {VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT}, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
        VkBufferImageCopy region{};
        region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        region.imageExtent = {width, height, 1};
        vkCmdCopyBufferToImage(cmd, src, img, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
        image_barrier(cmd, img, VK_IMAGE_ASPECT_COLOR_BIT, {VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT},
                      VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                      {VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_READ_BIT},
                      VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    }));
    VkSamplerCreateInfo s{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    s.magFilter = s.minFilter = VK_FILTER_LINEAR;
    s.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
    s.addressModeU = wrap_u;
    s.addressModeV = wrap_v;
    s.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    s.maxLod = 0.0f;
    VkSampler sampler = VK_NULL_HANDLE;
    PBDSPLAT_VK_TRY(vkCreateSampler(ctx.vk(), &s, nullptr, &sampler));
    t.sampler_ = Sampler(ctx.vk(), sampler);
    return t;
}

} // namespace pbdsplat::gpu
