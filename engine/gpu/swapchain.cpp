#include "gpu/swapchain.h"

#include <algorithm>

namespace pbdsplat::gpu {

namespace {
core::Result<Semaphore> make_semaphore(VkDevice device) {
    VkSemaphoreCreateInfo info{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    VkSemaphore s = VK_NULL_HANDLE;
    PBDSPLAT_VK_TRY(vkCreateSemaphore(device, &info, nullptr, &s));
    return Semaphore(device, s);
}
} // namespace

core::Result<Swapchain> Swapchain::create(Context& ctx, VkSurfaceKHR surface, VkExtent2D wanted, bool vsync,
                                          uint32_t frames_in_flight) {
    VkBool32 supported = VK_FALSE;
    PBDSPLAT_VK_TRY(vkGetPhysicalDeviceSurfaceSupportKHR(ctx.device().physical(), ctx.device().queue_family(), surface, &supported));
    if (!supported)
        return core::make_error("device '" + ctx.caps().name + "' cannot present to this window (its queue has no present support)");
    Swapchain s;
    s.ctx_ = &ctx;
    s.surface_ = surface;
    s.vsync_ = vsync;
    for (uint32_t i = 0; i < std::max(1u, frames_in_flight); ++i) {
        auto sem = make_semaphore(ctx.vk());
        if (!sem.ok()) return sem.error();
        s.acquire_semaphores_.push_back(std::move(sem).value());
    }
    PBDSPLAT_TRY(s.build(wanted));
    return s;
}

Swapchain& Swapchain::operator=(Swapchain&& o) noexcept {
    if (this == &o) return *this;
    reset();
    ctx_ = o.ctx_;
    surface_ = o.surface_;
    swapchain_ = std::exchange(o.swapchain_, VK_NULL_HANDLE);
    vsync_ = o.vsync_;
    format_ = o.format_;
    extent_ = o.extent_;
    images_ = std::move(o.images_);
    views_ = std::move(o.views_);
    acquire_semaphores_ = std::move(o.acquire_semaphores_);
    present_semaphores_ = std::move(o.present_semaphores_);
    index_ = o.index_;
    acquired_ = std::exchange(o.acquired_, false);
    wait_ = o.wait_;
    signal_ = o.signal_;
    return *this;
}

void Swapchain::reset() {
    if (!ctx_) return;
    views_.clear();
    present_semaphores_.clear();
    if (swapchain_) vkDestroySwapchainKHR(ctx_->vk(), swapchain_, nullptr);
    swapchain_ = VK_NULL_HANDLE;
    images_.clear();
    acquire_semaphores_.clear();
}

namespace {
// The splats are shaded in linear space and written to a UNORM target: a UNORM swapchain
// shows them as the offscreen images do.
core::Result<VkSurfaceFormatKHR> choose_format(VkPhysicalDevice pd, VkSurfaceKHR surface) {
    uint32_t n = 0;
    PBDSPLAT_VK_TRY(vkGetPhysicalDeviceSurfaceFormatsKHR(pd, surface, &n, nullptr));
    std::vector<VkSurfaceFormatKHR> formats(n);
    PBDSPLAT_VK_TRY(vkGetPhysicalDeviceSurfaceFormatsKHR(pd, surface, &n, formats.data()));
    if (formats.empty()) return core::make_error("the window surface offers no image formats");
    VkSurfaceFormatKHR chosen = formats.front();
    for (const VkSurfaceFormatKHR& f : formats)
        if ((f.format == VK_FORMAT_B8G8R8A8_UNORM || f.format == VK_FORMAT_R8G8B8A8_UNORM) && f.colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR)
            chosen = f;
    return chosen;
}

core::Result<VkPresentModeKHR> choose_mode(VkPhysicalDevice pd, VkSurfaceKHR surface, bool vsync) {
    uint32_t mode_count = 0;
    PBDSPLAT_VK_TRY(vkGetPhysicalDeviceSurfacePresentModesKHR(pd, surface, &mode_count, nullptr));
    std::vector<VkPresentModeKHR> modes(mode_count);
    PBDSPLAT_VK_TRY(vkGetPhysicalDeviceSurfacePresentModesKHR(pd, surface, &mode_count, modes.data()));
    if (!vsync)
        for (VkPresentModeKHR m : {VK_PRESENT_MODE_MAILBOX_KHR, VK_PRESENT_MODE_IMMEDIATE_KHR})
            if (std::find(modes.begin(), modes.end(), m) != modes.end()) return m;
    return VK_PRESENT_MODE_FIFO_KHR;  // always there: vsync
}
} // namespace

core::Status Swapchain::build(VkExtent2D wanted) {
    const VkPhysicalDevice pd = ctx_->device().physical();
    VkSurfaceCapabilitiesKHR caps{};
    PBDSPLAT_VK_TRY(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(pd, surface_, &caps));
    auto format = choose_format(pd, surface_);
    if (!format.ok()) return format.error();
    const VkSurfaceFormatKHR chosen = format.value();
    auto present_mode = choose_mode(pd, surface_, vsync_);
    if (!present_mode.ok()) return present_mode.error();
    const VkPresentModeKHR mode = present_mode.value();
    VkExtent2D extent = caps.currentExtent;
    if (extent.width == UINT32_MAX) {
        extent.width = std::clamp(wanted.width, caps.minImageExtent.width, caps.maxImageExtent.width);
        extent.height = std::clamp(wanted.height, caps.minImageExtent.height, caps.maxImageExtent.height);
    }
    if (extent.width == 0 || extent.height == 0) return core::make_error("the window has no area (minimised)");
    if (!(caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_DST_BIT))
        return core::make_error("the window surface's images cannot be copied into (no TRANSFER_DST usage)");
    uint32_t count = std::max(caps.minImageCount + 1, 2u);
    if (caps.maxImageCount > 0) count = std::min(count, caps.maxImageCount);

    VkSwapchainCreateInfoKHR info{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
    info.surface = surface_;
    info.minImageCount = count;
    info.imageFormat = chosen.format;
    info.imageColorSpace = chosen.colorSpace;
    info.imageExtent = extent;
    info.imageArrayLayers = 1;
    info.imageUsage = VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
    info.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
    info.preTransform = caps.currentTransform;
    info.compositeAlpha = (caps.supportedCompositeAlpha & VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR)
                              ? VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR
                              : VkCompositeAlphaFlagBitsKHR(caps.supportedCompositeAlpha & -caps.supportedCompositeAlpha);
    info.presentMode = mode;
    info.clipped = VK_TRUE;
    info.oldSwapchain = swapchain_;
    VkSwapchainKHR created = VK_NULL_HANDLE;
    PBDSPLAT_VK_TRY(vkCreateSwapchainKHR(ctx_->vk(), &info, nullptr, &created));
    views_.clear();
    present_semaphores_.clear();
    if (swapchain_) vkDestroySwapchainKHR(ctx_->vk(), swapchain_, nullptr);
    swapchain_ = created;
    format_ = chosen.format;
    extent_ = extent;

    return create_views();
}

core::Status Swapchain::create_views() {
    uint32_t image_count = 0;
    PBDSPLAT_VK_TRY(vkGetSwapchainImagesKHR(ctx_->vk(), swapchain_, &image_count, nullptr));
    images_.resize(image_count);
    PBDSPLAT_VK_TRY(vkGetSwapchainImagesKHR(ctx_->vk(), swapchain_, &image_count, images_.data()));
    for (VkImage image : images_) {
        VkImageViewCreateInfo v{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
        v.image = image;
        v.viewType = VK_IMAGE_VIEW_TYPE_2D;
        v.format = format_;
        v.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        VkImageView view = VK_NULL_HANDLE;
        PBDSPLAT_VK_TRY(vkCreateImageView(ctx_->vk(), &v, nullptr, &view));
        views_.emplace_back(ctx_->vk(), view);
        auto sem = make_semaphore(ctx_->vk());
        if (!sem.ok()) return sem.error();
        present_semaphores_.push_back(std::move(sem).value());
    }
    acquired_ = false;
    return core::Status::success();
}

core::Status Swapchain::recreate(VkExtent2D wanted) {
    PBDSPLAT_VK_TRY(vkDeviceWaitIdle(ctx_->vk()));
    return build(wanted);
}

core::Result<bool> Swapchain::acquire(uint32_t frame_slot) {
    acquired_ = false;
    const VkSemaphore s = acquire_semaphores_[frame_slot % acquire_semaphores_.size()].get();
    const VkResult r = vkAcquireNextImageKHR(ctx_->vk(), swapchain_, UINT64_MAX, s, VK_NULL_HANDLE, &index_);
    if (r == VK_ERROR_OUT_OF_DATE_KHR) return false;
    if (r != VK_SUCCESS && r != VK_SUBOPTIMAL_KHR) return core::make_error(std::string("vkAcquireNextImageKHR: ") + vk_result_name(r));
    wait_.semaphore = s;
    // The graph's first barrier on the image starts from all commands: wait before any of them.
    wait_.stageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
    signal_.semaphore = present_semaphores_[index_].get();
    signal_.stageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
    acquired_ = true;
    return true;
}

core::Result<bool> Swapchain::present() {
    if (!acquired_) return false;
    acquired_ = false;
    VkPresentInfoKHR info{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
    const VkSemaphore wait = signal_.semaphore;
    info.waitSemaphoreCount = 1;
    info.pWaitSemaphores = &wait;
    info.swapchainCount = 1;
    info.pSwapchains = &swapchain_;
    info.pImageIndices = &index_;
    const VkResult r = vkQueuePresentKHR(ctx_->device().queue(), &info);
    if (r == VK_ERROR_OUT_OF_DATE_KHR || r == VK_SUBOPTIMAL_KHR) return false;
    if (r != VK_SUCCESS) return core::make_error(std::string("vkQueuePresentKHR: ") + vk_result_name(r));
    return true;
}

} // namespace pbdsplat::gpu
