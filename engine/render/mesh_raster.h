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
#include "render/mesh_textures.h"
#include "render/offscreen_target.h"
#include "render/splat_renderer.h"

namespace pbdsplat::render {

enum class MeshView { mask, shaded };

// A textured mesh for MeshView::shaded: texture coordinates per vertex (v down, as
// asset::Texture stores rows) and each triangle's texture (an index into the textures given to
// set_textures(), or -1 for none).
struct MeshTexturing {
    std::span<const Vec2f> uv;
    std::span<const int32_t> triangle_texture;
};

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
    // `texturing`, when given, has the shaded view multiply the colours by the textures.
    core::Status set_mesh(std::span<const Vec4f> positions, std::span<const std::array<uint32_t, 3>> triangles,
                          std::span<const Vec3f> normals = {}, uint32_t slot = 0, std::span<const Vec3f> colors = {},
                          const MeshTexturing* texturing = nullptr);
    // The textures MeshTexturing indexes; call while no frame that reads them is in flight.
    core::Status set_textures(std::span<const MeshTexture> textures) { return textures_.set(*ctx_, textures); }
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
    core::Status set_texturing(uint32_t slot_index, std::span<const std::array<uint32_t, 3>> triangles, const MeshTexturing& texturing);
    // A run of the index buffer drawn with one texture.
    struct Run {
        uint32_t first_index = 0, index_count = 0;
        int32_t texture = -1;
    };
    struct Slot {
        gpu::Buffer vertices, normals, colors, uvs, indices;
        std::vector<Run> runs;  // the triangles grouped by texture (one run, untextured, without)
        bool colored = false;  // colors holds a mesh's own; else all ones
    };
    std::vector<Slot> slots_;
    EnvironmentTexture environment_;
    MeshTextureSets textures_;
    gpu::DescriptorSetLayout set_layout_;
    gpu::UniformSets uniforms_;
    gpu::PipelineLayout layout_;
    gpu::Pipeline mask_, shaded_;
};

} // namespace pbdsplat::render
