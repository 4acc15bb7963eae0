#pragma once
// Rasterises the deformed simulation mesh: as a coverage mask (the reference the splats'
// hole ratio and silhouette IoU are measured against) or lit with the splats' own shading (the
// mesh-based pipeline the paper compares against, for side-by-side views and error metrics).
#include <array>
#include <memory>
#include <span>

#include "core/image.h"
#include "gpu/buffer.h"
#include "gpu/device_handle.h"
#include "gpu/pipeline.h"
#include "gpu/uniform_sets.h"
#include "render/environment_texture.h"
#include "render/frame_inputs.h"
#include "render/offscreen_target.h"
#include "render/splat_renderer.h"

namespace pbdsplat::render {

enum class MeshView { mask, shaded };

struct MeshRasterOptions {
    uint32_t width = 1280, height = 720;
    size_t max_vertices = 0, max_triangles = 0;
    // The same environment the splat renderer would use (see RendererOptions).
    std::string environment_map;
    Vec3f sky_sun{0.4f, 0.7f, 0.6f};
    // Copies of the mesh buffers, one per frame in flight, so the CPU never writes what the
    // GPU may still read.
    uint32_t slots = 1;
};

class MeshRaster {
public:
    static core::Result<std::unique_ptr<MeshRaster>> create(gpu::Context& ctx, const MeshRasterOptions& options);

    // Copies the mesh into the (host-visible) vertex and index buffers; call while no frame
    // using them is in flight. `normals` (one per position) are needed for MeshView::shaded;
    // `colors` (linear, one per position), when given, multiply the albedo: a model's own look.
    core::Status set_mesh(std::span<const Vec4f> positions, std::span<const std::array<uint32_t, 3>> triangles,
                          std::span<const Vec3f> normals = {}, uint32_t slot = 0, std::span<const Vec3f> colors = {});
    // Draws into the target (in attachment layouts); the caller's frame graph places the
    // barriers (uses::color_attachment etc.). A mask clears to transparent black, a shaded view
    // to the frame's background.
    void draw(VkCommandBuffer cmd, const FrameInputs& inputs, MeshView view = MeshView::mask,
              const Vec3f& albedo = Vec3f(0.8f, 0.2f, 0.2f), uint32_t slot = 0);
    void readback(VkCommandBuffer cmd) { target_.record_readback(cmd, 0); }
    core::ImageRgba8 read() const { return target_.read(0); }

    VkImage color_image() const { return target_.color().handle(); }
    VkImage depth_image() const { return target_.depth().handle(); }
    VkBuffer readback_buffer() const { return target_.readback_buffer(0); }
    uint32_t width() const { return target_.width(); }
    uint32_t height() const { return target_.height(); }

private:
    MeshRaster() = default;
    // The steps of create(), in order.
    core::Status create_slots(gpu::Context& ctx, const MeshRasterOptions& options);
    core::Status create_frame_set(gpu::Context& ctx);
    core::Status create_pipelines(gpu::Context& ctx);
    gpu::Context* ctx_ = nullptr;
    OffscreenTarget target_;
    struct Slot {
        gpu::Buffer vertices, normals, colors, indices;
        uint32_t index_count = 0;
        bool colored = false;  // colors holds a mesh's own; else all ones
    };
    std::vector<Slot> slots_;
    EnvironmentTexture environment_;
    gpu::DescriptorSetLayout set_layout_;
    gpu::UniformSets uniforms_;
    gpu::PipelineLayout layout_;
    gpu::Pipeline mask_, shaded_;
};

} // namespace pbdsplat::render
