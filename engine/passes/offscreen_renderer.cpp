#include "passes/offscreen_renderer.h"

namespace pbdsplat::passes {

core::Result<std::unique_ptr<OffscreenRenderer>> OffscreenRenderer::create(gpu::Context& ctx, const render::RendererOptions& options,
                                                                           Presenter* presenter) {
    auto r = std::unique_ptr<OffscreenRenderer>(new OffscreenRenderer());
    auto renderer = render::SplatRenderer::create(ctx, options);
    if (!renderer.ok()) return renderer.error();
    r->renderer_ = std::move(renderer).value();
    r->presenter_ = presenter;
    r->gpu_sort_ = options.gpu_sort;
    r->readback_ = presenter == nullptr;
    PBDSPLAT_TRY(r->build_graph());
    return r;
}

core::Status OffscreenRenderer::build_graph() {
    graph_ = graph::FrameGraph();
    const auto input = import_gpu_input(graph_, input_);
    // Without a sink the readback pass is culled: a window shows frames without copying them out.
    const auto sink = graph_.import("image", readback_ ? &sink_ : static_cast<ImageSink*>(nullptr));
    const auto status = graph_.import("upload status", &upload_status_, true);
    const auto drawn = add_gpu_passes(graph_, *renderer_, resources_, input, status, sink, gpu_sort_);
    if (presenter_) {
        const PresentSources sources{drawn, {}, renderer_->width(), renderer_->height(),
                                     [renderer = renderer_.get()] { return renderer->slot(); }};
        presenter_->add_passes(graph_, sources);
    }
    return graph_.compile();
}

core::Status OffscreenRenderer::set_readback(bool readback) {
    if (readback == readback_) return core::Status::success();
    readback_ = readback;
    return build_graph();
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
    if (!texcoords_.empty() && texcoords_.size() != records.size())
        return core::make_error("textured splats need one texture entry per record (" + std::to_string(texcoords_.size()) + " for " +
                                std::to_string(records.size()) + ")");
    auto cmd = renderer_->begin_frame();
    if (!cmd.ok()) return cmd.error();
    input_.splats.records = records;
    input_.splats.texcoords = texcoords_;
    input_.splats.changed.assign(changed.begin(), changed.end());
    input_.splats.shapes = shapes;
    input_.splats.sh = sh;
    input_.frame = inputs;
    resources_.refresh(*renderer_);
    graph::ExecuteContext ctx{cmd.value(), 0};
    graph_.execute(ctx);
    // Submitted even on failure, so the frame ring stays consistent.
    PBDSPLAT_TRY(renderer_->end_frame(presenter_ ? presenter_->wait_semaphore() : nullptr,
                                      presenter_ ? presenter_->signal_semaphore() : nullptr));
    return upload_status_;
}

} // namespace pbdsplat::passes
