#pragma once
// What every windowed view holds: the window, the device, its swapchain, the HUD overlay and the
// presenter that takes a frame graph's image to the screen. Destroyed in reverse order after the
// device is idle; a view that adds GPU objects of its own derives and frees them first.
#include <memory>
#include <string>

#include "demo/presenter.h"
#include "demo/window.h"
#include "gpu/swapchain.h"
#include "render/overlay.h"

namespace pbdsplat::demo {

inline constexpr uint32_t k_window_frames_in_flight = 2;

struct WindowSession {
    std::unique_ptr<Window> window;
    std::unique_ptr<gpu::Context> ctx;
    VkSurfaceKHR surface = VK_NULL_HANDLE;
    gpu::Swapchain swapchain;
    std::unique_ptr<render::OverlayPass> overlay;
    std::unique_ptr<SwapchainPresenter> presenter;
    virtual ~WindowSession();

    // Opens the window (width x height), a device that can present to it (`device`: a name
    // filter; `validation`: the Khronos layer on), the swapchain, overlay and presenter.
    core::Status open(const std::string& title, uint32_t width, uint32_t height, bool vsync, bool validation,
                      const std::string& device);
    // Remakes the swapchain when the window's size changed; false while it is minimised.
    core::Result<bool> follow_window_size();
    // Presents the frame the presenter's passes drew (remaking the swapchain when out of date).
    core::Status present();
};

} // namespace pbdsplat::demo
