#pragma once
// A 2D VkImage with one view over all of it, and its sub-allocated memory; move-only.
#include "gpu/context.h"
#include "gpu/device_handle.h"

namespace pbdsplat::gpu {

class Image {
public:
    Image() = default;
    static core::Result<Image> create_2d(Context& ctx, uint32_t width, uint32_t height, VkFormat format,
                                         VkImageUsageFlags usage, VkImageAspectFlags aspect);
    Image(Image&& o) noexcept { *this = std::move(o); }
    Image& operator=(Image&& o) noexcept;
    Image(const Image&) = delete;
    Image& operator=(const Image&) = delete;
    ~Image() { reset(); }
    void reset();

    VkImage handle() const { return image_; }
    VkImageView view() const { return view_.get(); }
    VkFormat format() const { return format_; }
    VkImageAspectFlags aspect() const { return aspect_; }
    uint32_t width() const { return width_; }
    uint32_t height() const { return height_; }

private:
    Context* ctx_ = nullptr;
    VkImage image_ = VK_NULL_HANDLE;
    ImageView view_;
    VkFormat format_ = VK_FORMAT_UNDEFINED;
    VkImageAspectFlags aspect_ = 0;
    uint32_t width_ = 0, height_ = 0;
    Allocation allocation_;
};

} // namespace pbdsplat::gpu
