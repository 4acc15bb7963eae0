#pragma once
// The window's swapchain: images to draw into and present, remade when the window changes.
// The surface comes from the window system (the demo's GLFW window); this room never sees it.
#include <vector>

#include "gpu/context.h"
#include "gpu/device_handle.h"

namespace pbdsplat::gpu {

using Surface = VkSurfaceKHR;

class Swapchain {
public:
    // One acquire semaphore per frame slot (reused once the slot's fence has signalled), one
    // present semaphore per image.
    static core::Result<Swapchain> create(Context& ctx, VkSurfaceKHR surface, VkExtent2D wanted, bool vsync,
                                          uint32_t frames_in_flight);
    Swapchain() = default;
    Swapchain(Swapchain&& o) noexcept { *this = std::move(o); }
    Swapchain& operator=(Swapchain&& o) noexcept;
    Swapchain(const Swapchain&) = delete;
    Swapchain& operator=(const Swapchain&) = delete;
    ~Swapchain() { reset(); }

    // Waits for the device, then makes new images for `wanted` (the window's framebuffer size).
    core::Status recreate(VkExtent2D wanted);
    // The next image; false (not an error) when the swapchain is out of date and must be
    // remade. After true, image() is the image to draw and the submit must wait on
    // acquire_wait() and signal present_signal().
    core::Result<bool> acquire(uint32_t frame_slot);
    // Presents the acquired image; false when the swapchain should be remade.
    core::Result<bool> present();
    bool acquired() const { return acquired_; }

    VkImage image() const { return acquired_ ? images_[index_] : VK_NULL_HANDLE; }
    VkImageView view() const { return acquired_ ? views_[index_].get() : VK_NULL_HANDLE; }
    VkFormat format() const { return format_; }
    VkExtent2D extent() const { return extent_; }
    const VkSemaphoreSubmitInfo* acquire_wait() const { return acquired_ ? &wait_ : nullptr; }
    const VkSemaphoreSubmitInfo* present_signal() const { return acquired_ ? &signal_ : nullptr; }

private:
    core::Status build(VkExtent2D wanted);
    core::Status create_views();  // of the swapchain's images, with a present semaphore each
    void reset();
    Context* ctx_ = nullptr;
    VkSurfaceKHR surface_ = VK_NULL_HANDLE;
    VkSwapchainKHR swapchain_ = VK_NULL_HANDLE;
    bool vsync_ = true;
    VkFormat format_ = VK_FORMAT_UNDEFINED;
    VkExtent2D extent_{};
    std::vector<VkImage> images_;
    std::vector<ImageView> views_;
    std::vector<Semaphore> acquire_semaphores_;  // per frame slot
    std::vector<Semaphore> present_semaphores_;  // per image
    uint32_t index_ = 0;
    bool acquired_ = false;
    VkSemaphoreSubmitInfo wait_{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
    VkSemaphoreSubmitInfo signal_{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
};

} // namespace pbdsplat::gpu
