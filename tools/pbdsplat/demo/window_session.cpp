#include "demo/window_session.h"

namespace pbdsplat::demo {

WindowSession::~WindowSession() {
    if (ctx) (void)vkDeviceWaitIdle(ctx->vk());
    presenter.reset();
    overlay.reset();
    swapchain = gpu::Swapchain();
    if (surface) vkDestroySurfaceKHR(ctx->instance().handle(), surface, nullptr);
}

core::Status WindowSession::open(const std::string& title, uint32_t width, uint32_t height, bool vsync, bool validation,
                                 const std::string& device) {
    auto w = Window::create(title, width, height);
    if (!w.ok()) return w.error();
    window = std::move(w).value();
    gpu::ContextOptions co;
    co.instance.validation = validation;
    co.instance.surface = true;
    co.instance.extra_extensions = Window::required_extensions();
    co.device.name_filter = device;
    co.device.swapchain = true;
    auto c = gpu::Context::create(co);
    if (!c.ok()) return c.error();
    ctx = std::move(c).value();
    auto s = window->create_surface(ctx->instance().handle());
    if (!s.ok()) return s.error();
    surface = s.value();
    auto chain = gpu::Swapchain::create(*ctx, surface, window->framebuffer_size(), vsync, k_window_frames_in_flight);
    if (!chain.ok()) return chain.error();
    swapchain = std::move(chain).value();
    const VkExtent2D ext = swapchain.extent();
    auto o = render::OverlayPass::create(*ctx, ext.width, ext.height, swapchain.format(), k_window_frames_in_flight);
    if (!o.ok()) return o.error();
    overlay = std::move(o).value();
    presenter = std::make_unique<SwapchainPresenter>(swapchain, *overlay);
    return core::Status::success();
}

core::Result<bool> WindowSession::follow_window_size() {
    const VkExtent2D fb = window->framebuffer_size();
    if (fb.width == 0 || fb.height == 0) return false;
    if (fb.width != swapchain.extent().width || fb.height != swapchain.extent().height) PBDSPLAT_TRY(swapchain.recreate(fb));
    return true;
}

core::Status WindowSession::present() {
    PBDSPLAT_TRY(presenter->status());
    bool fresh = presenter->acquired();
    if (fresh) {
        auto presented = swapchain.present();
        if (!presented.ok()) return presented.error();
        fresh = presented.value();
    }
    if (!fresh) PBDSPLAT_TRY(swapchain.recreate(window->framebuffer_size()));
    return core::Status::success();
}

} // namespace pbdsplat::demo
