#include "demo/presenter.h"

#include <algorithm>

namespace pbdsplat::demo {

namespace {
// Clears and blits are transfer commands outside the copy stage: their uses name all of them.
constexpr render::Use k_copy_destination{{VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT},
                                         VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL};
constexpr render::Use k_blit_source{{VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT},
                                    VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL};
constexpr render::Use k_present{{VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_NONE}, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR};
constexpr render::Use k_overlay_target{{VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                                        VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT},
                                       VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};

// Copies the middle `src_w` columns of a width x height image into `dst` (a rectangle of the
// window), scaled.
void blit(VkCommandBuffer cmd, VkImage src, uint32_t width, uint32_t height, uint32_t src_w, VkImage dst, int32_t x,
          int32_t y, uint32_t w, uint32_t h) {
    VkImageBlit region{};
    region.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.dstSubresource = region.srcSubresource;
    const int32_t x0 = int32_t((width - src_w) / 2);
    region.srcOffsets[0] = {x0, 0, 0};
    region.srcOffsets[1] = {x0 + int32_t(src_w), int32_t(height), 1};
    region.dstOffsets[0] = {x, y, 0};
    region.dstOffsets[1] = {x + int32_t(w), y + int32_t(h), 1};
    vkCmdBlitImage(cmd, src, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, dst, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region,
                   VK_FILTER_LINEAR);
}
} // namespace

Letterbox fit(uint32_t image_width, uint32_t image_height, VkExtent2D window) {
    Letterbox b;
    if (image_width == 0 || image_height == 0 || window.width == 0 || window.height == 0) return b;
    const double scale = std::min(double(window.width) / image_width, double(window.height) / image_height);
    b.width = std::max(1u, uint32_t(image_width * scale));
    b.height = std::max(1u, uint32_t(image_height * scale));
    b.x = int32_t((window.width - b.width) / 2);
    b.y = int32_t((window.height - b.height) / 2);
    return b;
}

SwapchainPresenter::SwapchainPresenter(gpu::Swapchain& swapchain, render::OverlayPass& overlay)
    : swapchain_(swapchain), overlay_(overlay) {
    overlay_image_.image = overlay.image();
}

void SwapchainPresenter::add_passes(graph::FrameGraph& g, const passes::PresentSources& s) {
    auto target = g.import("swapchain image", &target_);
    auto overlay = g.import("overlay image", &overlay_image_);
    const auto slot = s.slot;
    // Acquired inside the frame, after the frame slot's fence has been waited for: the slot's
    // acquire semaphore is free again by then.
    g.add_pass("acquire", graph::PassKind::cpu, [&](graph::PassBuilder& b) {
        target = b.write(target);
        return [this, slot](const graph::PassResources&, graph::ExecuteContext&) {
            auto ok = swapchain_.acquire(slot());
            if (!ok.ok()) status_ = ok.error();
            target_.image = swapchain_.image();  // null when out of date: the passes below skip
        };
    });
    // The whole image first (the letterbox bars), then the frame into its rectangle: two
    // passes, so the graph orders the two writes.
    g.add_pass("present clear", graph::PassKind::gpu, [&](graph::PassBuilder& b) {
        target = b.write(target, passes::to_graph(k_copy_destination));
        return [this](const graph::PassResources&, graph::ExecuteContext& c) {
            if (!target_.image) return;
            const VkClearColorValue bars{{0.02f, 0.02f, 0.025f, 1.0f}};
            const VkImageSubresourceRange all{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
            vkCmdClearColorImage(c.cmd, target_.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &bars, 1, &all);
        };
    });
    const bool with_mesh = s.mesh.version != UINT32_MAX && (view_ == scene::DisplayView::mesh || view_ == scene::DisplayView::side_by_side);
    const scene::DisplayView view = view_;
    g.add_pass("present copy", graph::PassKind::gpu, [&](graph::PassBuilder& b) {
        b.read(s.splats, passes::to_graph(k_blit_source));
        if (with_mesh) b.read(s.mesh, passes::to_graph(k_blit_source));
        target = b.write(target, passes::to_graph(k_copy_destination));
        return [this, s, view, with_mesh](const graph::PassResources& r, graph::ExecuteContext& c) {
            if (!target_.image) return;
            const Letterbox box = fit(s.width, s.height, swapchain_.extent());
            const VkImage splats = r.read(s.splats).image;
            const VkImage mesh = with_mesh ? r.read(s.mesh).image : VK_NULL_HANDLE;
            if (view == scene::DisplayView::side_by_side && with_mesh) {
                // The middle half of each image, side by side, at the full image's scale.
                const uint32_t half = box.width / 2;
                blit(c.cmd, splats, s.width, s.height, s.width / 2, target_.image, box.x, box.y, half, box.height);
                blit(c.cmd, mesh, s.width, s.height, s.width / 2, target_.image, box.x + int32_t(half), box.y,
                     box.width - half, box.height);
            } else {
                blit(c.cmd, view == scene::DisplayView::mesh && with_mesh ? mesh : splats, s.width, s.height, s.width,
                     target_.image, box.x, box.y, box.width, box.height);
            }
        };
    });
    g.add_pass("overlay upload", graph::PassKind::gpu, [&](graph::PassBuilder& b) {
        overlay = b.write(overlay, passes::to_graph(render::uses::copy_destination));
        return [this, slot](const graph::PassResources&, graph::ExecuteContext& c) { overlay_.record_upload(c.cmd, slot()); };
    });
    g.add_pass("overlay", graph::PassKind::gpu, [&](graph::PassBuilder& b) {
        b.read(overlay, passes::to_graph(render::uses::overlay_sampled));
        target = b.write(target, passes::to_graph(k_overlay_target));
        return [this](const graph::PassResources&, graph::ExecuteContext& c) {
            if (target_.image) overlay_.record_draw(c.cmd, swapchain_.view(), swapchain_.extent());
        };
    });
    g.add_pass("present", graph::PassKind::gpu, [&](graph::PassBuilder& b) {
        b.read(target, passes::to_graph(k_present));
        b.side_effect();
        return [](const graph::PassResources&, graph::ExecuteContext&) {};  // the layout change is the pass
    });
}

} // namespace pbdsplat::demo
