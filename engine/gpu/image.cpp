#include "gpu/image.h"

#include <utility>

namespace pbdsplat::gpu {

core::Result<Image> Image::create_2d(Context& ctx, uint32_t width, uint32_t height, VkFormat format,
                                     VkImageUsageFlags usage, VkImageAspectFlags aspect) {
    if (width == 0 || height == 0 || width > 16384 || height > 16384)
        return core::make_error("image size " + std::to_string(width) + "x" + std::to_string(height) +
                                " is out of range (1..16384 each way)");
    Image img;
    img.ctx_ = &ctx;
    img.format_ = format;
    img.aspect_ = aspect;
    img.width_ = width;
    img.height_ = height;
    VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    info.imageType = VK_IMAGE_TYPE_2D;
    info.format = format;
    info.extent = {width, height, 1};
    info.mipLevels = 1;
    info.arrayLayers = 1;
    info.samples = VK_SAMPLE_COUNT_1_BIT;
    info.tiling = VK_IMAGE_TILING_OPTIMAL;
    info.usage = usage;
    info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    PBDSPLAT_VK_TRY(vkCreateImage(ctx.vk(), &info, nullptr, &img.image_));
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(ctx.vk(), img.image_, &req);
    auto alloc = ctx.memory().allocate(req, MemoryUsage::device_local);
    if (!alloc.ok()) return alloc.error();
    img.allocation_ = alloc.value();
    PBDSPLAT_VK_TRY(vkBindImageMemory(ctx.vk(), img.image_, img.allocation_.memory, img.allocation_.offset));

    VkImageViewCreateInfo view{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    view.image = img.image_;
    view.viewType = VK_IMAGE_VIEW_TYPE_2D;
    view.format = format;
    view.subresourceRange = {aspect, 0, 1, 0, 1};
    VkImageView v = VK_NULL_HANDLE;
    PBDSPLAT_VK_TRY(vkCreateImageView(ctx.vk(), &view, nullptr, &v));
    img.view_ = ImageView(ctx.vk(), v);
    return img;
}

Image& Image::operator=(Image&& o) noexcept {
    if (this != &o) {
        reset();
        ctx_ = std::exchange(o.ctx_, nullptr);
        image_ = std::exchange(o.image_, VK_NULL_HANDLE);
        view_ = std::move(o.view_);
        format_ = o.format_;
        aspect_ = o.aspect_;
        width_ = o.width_;
        height_ = o.height_;
        allocation_ = std::exchange(o.allocation_, Allocation{});
    }
    return *this;
}

void Image::reset() {
    if (!ctx_) return;
    view_.reset();
    if (image_ != VK_NULL_HANDLE) vkDestroyImage(ctx_->vk(), image_, nullptr);
    ctx_->memory().free(allocation_);
    image_ = VK_NULL_HANDLE;
    allocation_ = {};
    ctx_ = nullptr;
}

} // namespace pbdsplat::gpu
