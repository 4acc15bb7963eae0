#pragma once
// Takes a frame to the window: acquire a swapchain image, copy the splat (and mesh) image into
// it, blend the overlay over it, leave it ready to present. Each step is a pass of the
// runtime's frame graph, so the graph places every barrier.
#include <memory>

#include "gpu/swapchain.h"
#include "render/overlay.h"
#include "passes/gpu_passes.h"
#include "scene/scene_runtime.h"

namespace pbdsplat::demo {

// Where the rendered image lands in the window: the largest rectangle of its aspect ratio.
struct Letterbox {
    int32_t x = 0, y = 0;
    uint32_t width = 0, height = 0;
};
Letterbox fit(uint32_t image_width, uint32_t image_height, VkExtent2D window);

class SwapchainPresenter final : public passes::Presenter {
public:
    SwapchainPresenter(gpu::Swapchain& swapchain, render::OverlayPass& overlay);

    void add_passes(graph::FrameGraph& g, const passes::PresentSources& sources) override;
    const VkSemaphoreSubmitInfo* wait_semaphore() const override { return swapchain_.acquire_wait(); }
    const VkSemaphoreSubmitInfo* signal_semaphore() const override { return swapchain_.present_signal(); }

    void set_view(scene::DisplayView view) { view_ = view; }
    // Set by the acquire pass: false when the swapchain is out of date (the frame shows nothing
    // and the owner remakes the swapchain).
    bool acquired() const { return swapchain_.acquired(); }
    const core::Status& status() const { return status_; }

private:
    gpu::Swapchain& swapchain_;
    render::OverlayPass& overlay_;
    scene::DisplayView view_ = scene::DisplayView::splats;
    graph::GpuImageRef target_{VK_NULL_HANDLE, VK_IMAGE_ASPECT_COLOR_BIT};
    graph::GpuImageRef overlay_image_{VK_NULL_HANDLE, VK_IMAGE_ASPECT_COLOR_BIT};
    core::Status status_;
};

} // namespace pbdsplat::demo
