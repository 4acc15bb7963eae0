#pragma once
// Gaussian records in, image out: the GPU passes alone in a frame graph. For tools and tests
// that render records they made themselves, and, given a presenter, for a window showing a
// static capture; scenes use SceneRuntime.
#include <memory>
#include <span>

#include "passes/gpu_passes.h"

namespace pbdsplat::passes {

class OffscreenRenderer {
public:
    // `presenter`: also takes each frame to a window (its passes join the graph, and each
    // frame's submit waits on and signals its semaphores); it must outlive the renderer. A
    // presenting renderer reads frames back only after set_readback(true).
    static core::Result<std::unique_ptr<OffscreenRenderer>> create(gpu::Context& ctx, const render::RendererOptions& options,
                                                                   Presenter* presenter = nullptr);

    // Records and submits one frame. `changed` lists the byte ranges of `records` that differ
    // from the previous frame; empty means all of them. `shapes`: one per record for a renderer
    // created anisotropic; `sh`: one per record for a renderer created with an sh_degree.
    core::Status render(std::span<const splat::GaussianRecord> records, const render::FrameInputs& inputs,
                        std::span<const gpu::ByteRange> changed = {}, std::span<const splat::GaussianShape> shapes = {},
                        std::span<const splat::GaussianSH> sh = {});
    // The surface mesh for the next render()s' occluders (a renderer created with
    // options.occluders, frames with SplatStyle::mesh_occluders); the spans must outlive them.
    void set_occluders(std::span<const Vec4f> positions, std::span<const std::array<uint32_t, 3>> triangles, size_t one_sided = 0) {
        input_.occluders.positions = positions;
        input_.occluders.triangles = triangles;
        input_.occluders.one_sided = one_sided;
    }
    // Where a textured model's texture lies on each record of the next render()s (a renderer
    // created with options.textures; one per record, or none); the span must outlive them.
    void set_texcoords(std::span<const splat::GaussianTexcoord> texcoords) { texcoords_ = texcoords; }
    core::Status set_textures(std::span<const render::MeshTexture> textures) { return renderer_->set_textures(textures); }
    // Whether each frame is copied out for finish() (always, unless presenting).
    core::Status set_readback(bool readback);
    // Waits for the GPU and returns the last frame's image.
    core::Result<core::ImageRgba8> finish() { return renderer_->finish(); }
    render::GpuTimings timings() const { return renderer_->timings(); }
    gpu::UploadPath upload_path() const { return renderer_->upload_path(); }
    const graph::FrameGraph& graph() const { return graph_; }
    const render::SplatRenderer& splat_renderer() const { return *renderer_; }

private:
    OffscreenRenderer() = default;
    core::Status build_graph();
    std::unique_ptr<render::SplatRenderer> renderer_;
    Presenter* presenter_ = nullptr;
    bool gpu_sort_ = false, readback_ = true;
    GpuPassResources resources_;
    GpuFrameInput input_;
    std::span<const splat::GaussianTexcoord> texcoords_;
    core::Status upload_status_;  // what the frame's upload left
    ImageSink sink_;
    graph::FrameGraph graph_;
};

} // namespace pbdsplat::passes
