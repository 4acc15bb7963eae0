#include "passes/offscreen_renderer.h"

namespace pbdsplat::passes {

core::Result<std::unique_ptr<OffscreenRenderer>> OffscreenRenderer::create(gpu::Context& ctx, const render::RendererOptions& options,
                                                                           Presenter* presenter) {
    auto r = std::unique_ptr<OffscreenRenderer>(new OffscreenRenderer());
    auto renderer = render::SplatRenderer::create(ctx, options);
    if (!renderer.ok()) return renderer.error();
    r->renderer_ = std::move(renderer).value();
    const auto input = r->graph_.import("frame input", &r->input_);
    const auto sink = r->graph_.import("image", &r->sink_);
    const auto drawn = add_gpu_passes(r->graph_, *r->renderer_, r->resources_, input, sink, options.gpu_sort);
    r->presenter_ = presenter;
    if (presenter) {
        const PresentSources sources{drawn, {}, r->renderer_->width(), r->renderer_->height(),
                                     [renderer = r->renderer_.get()] { return renderer->slot(); }};
        presenter->add_passes(r->graph_, sources);
    }
    PBDSPLAT_TRY(r->graph_.compile());
    return r;
}

core::Status OffscreenRenderer::render(std::span<const splat::GaussianRecord> records, const render::FrameInputs& inputs,
                                       std::span<const gpu::ByteRange> changed, std::span<const splat::GaussianShape> shapes,
                                       std::span<const splat::GaussianSH> sh) {
    if (renderer_->anisotropic() && shapes.size() != records.size())
        return core::make_error("an anisotropic renderer needs one shape per record (" + std::to_string(shapes.size()) + " for " +
                                std::to_string(records.size()) + ")");
    if (renderer_->sh_degree() > 0 && sh.size() != records.size())
        return core::make_error("a renderer with view-dependent colour needs one colour record per Gaussian (" + std::to_string(sh.size()) +
                                " for " + std::to_string(records.size()) + ")");
    auto cmd = renderer_->begin_frame();
    if (!cmd.ok()) return cmd.error();
    input_.records = records;
    input_.changed.assign(changed.begin(), changed.end());
    input_.shapes = shapes;
    input_.sh = sh;
    input_.frame = inputs;
    resources_.refresh(*renderer_);
    graph::ExecuteContext ctx{cmd.value(), 0};
    graph_.execute(ctx);
    // Submitted even on failure, so the frame ring stays consistent.
    PBDSPLAT_TRY(renderer_->end_frame(presenter_ ? presenter_->wait_semaphore() : nullptr,
                                      presenter_ ? presenter_->signal_semaphore() : nullptr));
    return input_.upload_status;
}

} // namespace pbdsplat::passes
