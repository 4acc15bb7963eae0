#pragma once
// The GPU half of a frame: the resources (frames in flight, staging ring, record buffer, colour
// and depth targets, readback buffers, uniforms, timers) and the operations that use them
// (upload, draw, readback). The operations record no barriers: the frame graph derives them
// from the uses below.
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "core/image.h"
#include "gpu/frame_ring.h"
#include "gpu/gpu_timer.h"
#include "gpu/pipeline_counter.h"
#include "gpu/stream_buffer.h"
#include "gpu/texture.h"
#include "gpu/uniform_sets.h"
#include "render/environment_texture.h"
#include "render/frame_inputs.h"
#include "render/gpu_sort.h"
#include "render/gpu_use.h"
#include "render/mesh_textures.h"
#include "render/ground.h"
#include "render/normalised_blend.h"
#include "render/occluder_pass.h"
#include "render/offscreen_target.h"
#include "render/screen_bounds.h"
#include "render/splat_pass.h"
#include "splat/gaussian_record.h"

namespace pbdsplat::render {

struct RendererOptions {
    uint32_t width = 1280;
    uint32_t height = 720;
    uint32_t max_splats = 1u << 20;
    uint32_t frames_in_flight = 2;
    std::optional<gpu::UploadPath> upload_path;  // default: direct on unified memory, else staged
    std::optional<SplatPath> path;               // default: the best the device has
    // Equirectangular environment map (PNG or .hdr); empty: a procedural sky lit from the key
    // light's direction `sky_sun`.
    std::string environment_map;
    Vec3f sky_sun{0.4f, 0.7f, 0.6f};
    SplatShading shading = SplatShading::fragment;
    SplatCarrier carrier = SplatCarrier::quad;
    // Draw each splat with its own axes (upload_shapes every frame) instead of round. Not with
    // the GPU sort, which reorders only the records: sort on the CPU (both streams) instead.
    bool anisotropic = false;
    // Degrees of view-dependent colour to evaluate (upload_sh every frame); 0: none. The same
    // limit on sorting as anisotropic.
    uint32_t sh_degree = 0;
    // Textured splats: how many textures (at most SPLAT_MAX_TEXTURES; 0: none) the splats read
    // under their pixels where their entries in the texture stream say (upload_texcoords every
    // frame; the textures from set_textures). The pipelines are made for that many.
    uint32_t textures = 0;
    // Create the GPU depth sort (frames drawn with SplatOrder::gpu need it).
    bool gpu_sort = false;
    // Create normalised blending's accumulation image and passes (frames drawn with
    // Blend::normalised need them; the graph then declares the accumulation and resolve passes).
    bool normalised = false;
    // Create the mesh occluders (render/occluder_pass.h), for normalised blending or the paper's
    // disc under "over"; frames drawn with SplatStyle::mesh_occluders need them (and the graph
    // then declares their pass, and the disc's own pass after it).
    bool occluders = false;
};

// GPU milliseconds of the last finished frame, from timestamps (0 when the device has none).
struct GpuTimings {
    double upload_cpu_ms = 0.0;  // CPU: writing the records (in place, or into the staging ring)
    double upload_ms = 0.0;      // GPU: the staging copy (about 0 on the direct path)
    double sort_ms = 0.0;  // GPU: cull, radix sort and gather (0 without the GPU sort)
    double draw_ms = 0.0;  // every drawing pass below together
    // The drawing's parts (0 where they do not run): the splat pass proper (with normalised
    // blending or mesh occluders, its visibility depth only), the occluder mesh, the paper's
    // disc over the occluders, and normalised blending's sums and resolve.
    double splat_ms = 0.0, occluders_ms = 0.0, over_occluders_ms = 0.0, accumulate_ms = 0.0, resolve_ms = 0.0;
    double readback_ms = 0.0;
    uint64_t uploaded_bytes = 0;
    // What the splats' draws did (all zeros without pipeline-statistics queries): the splat pass
    // proper, the discs over occluders and the normalised sums together; the occluder mesh, the
    // ground and the resolve are left out.
    gpu::PipelineCounts splat_counts;
};

// How each operation uses what it touches.
namespace uses {
inline constexpr Use upload_write{{VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT}};
inline constexpr Use compute_read{{VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT}};
inline constexpr Use compute_write{{VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                                    VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT}};
inline constexpr Use indirect_read{{VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT, VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT}};
inline constexpr Use color_attachment{{VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                                       VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT},
                                      VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
inline constexpr Use depth_attachment{{VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                                       VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
                                           VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT},
                                      VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL};
inline constexpr Use color_copy_source{{VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT},
                                       VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL};
inline constexpr Use readback_write{{VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT}};
// How the splat pass reads its records: vertex attributes, or storage reads in the stage that
// pulls them.
Use records_read(SplatPath path);
// The streams beside the records (shapes, view-dependent colour) and their order, as the front
// stage reads them.
Use streams_read(SplatPath path);
} // namespace uses

class SplatRenderer {
public:
    static core::Result<std::unique_ptr<SplatRenderer>> create(gpu::Context& ctx, const RendererOptions& options);
    ~SplatRenderer();

    // Waits for the next slot's previous frame, collects its timings and starts recording.
    core::Result<VkCommandBuffer> begin_frame();
    // Submits the frame; a windowed frame waits on the swapchain image and signals its present.
    core::Status end_frame(const VkSemaphoreSubmitInfo* wait = nullptr, const VkSemaphoreSubmitInfo* signal = nullptr);
    uint32_t slot() const { return frames_.slot(); }
    uint32_t frames_in_flight() const { return options_.frames_in_flight; }
    // Waits for the GPU and returns the newest frame's image (read back by readback()).
    core::Result<core::ImageRgba8> finish();

    // Operations on the frame being recorded.
    core::Status upload(std::span<const splat::GaussianRecord> records, std::span<const gpu::ByteRange> changed);
    // The anisotropic splats' axes, one per record in the same order (options.anisotropic). They
    // are written in place into host-visible memory that only this frame's slot reads, so the
    // submit itself makes them visible: no copy, no barrier.
    core::Status upload_shapes(std::span<const splat::GaussianShape> shapes);
    // Degrees 1-3 of each record's colour (options.sh_degree > 0), written like the shapes.
    core::Status upload_sh(std::span<const splat::GaussianSH> sh);
    // Where a textured model's texture lies on each record, one per record in the same order
    // (options.textures > 0), written like the shapes.
    core::Status upload_texcoords(std::span<const splat::GaussianTexcoord> texcoords);
    // The textures the texture stream names (at most options.textures; the rest of the array a
    // white texel). Waits for the frames in flight: call it when the scene's models are known.
    core::Status set_textures(std::span<const MeshTexture> textures);
    // Culls and sorts the uploaded records far to near (needs options.gpu_sort); a following
    // draw() with SplatOrder::gpu draws the result.
    void sort(const FrameInputs& inputs, uint32_t count);
    // With Blend::normalised, draw() lays down the ground (unless mesh occluders draw it after
    // the mesh) and the visibility depth only;
    // accumulate() sums the front fragments and resolve() blends them over the colour target.
    // Both record nothing for other blends.
    // The draws make the pipelines their style needs the first time it comes (a shader compile
    // each, SplatPass::prepare); a failure to make one is returned by end_frame().
    void draw(const FrameInputs& inputs, uint32_t count);
    // Mesh occluders (options.occluders): the surface mesh for this frame's slot, then its pass
    // (and the ground after it), between draw() and accumulate(); records nothing unless the
    // style asks for them.
    // (`one_sided`: the leading triangles that close solids, OccluderPass::set_mesh.)
    core::Status set_occluders(std::span<const Vec4f> positions, std::span<const std::array<uint32_t, 3>> triangles, size_t one_sided = 0);
    void draw_occluders(const FrameInputs& inputs);
    // The paper's disc against the occluders, after draw_occluders(); records nothing for other
    // styles (draw() drew them).
    void draw_over_occluders(const FrameInputs& inputs, uint32_t count);
    void accumulate(const FrameInputs& inputs, uint32_t count);
    void resolve(const FrameInputs& inputs);
    void readback();

    // The resources the current frame uses (the record buffer differs per slot on the direct path).
    VkBuffer records_buffer() const { return records_.buffer(frames_.slot()); }
    VkImage color_image() const { return target_.color().handle(); }
    VkImage depth_image() const { return target_.depth().handle(); }
    bool has_normalised() const { return splat_.normalised(); }
    size_t splat_pipelines_made() const { return splat_.pipelines_made(); }
    bool has_occluders() const { return static_cast<bool>(occluders_.image().handle()); }
    VkImage occluder_image() const { return occluders_.image().handle(); }
    // How the splat passes read the occluders' distance image.
    Use occluder_read() const { return occluders_.sampled(); }
    VkImage accumulation_image(SumLayer layer) const { return has_normalised() ? blend_.accumulation(layer).handle() : VK_NULL_HANDLE; }
    VkBuffer readback_buffer() const { return target_.readback_buffer(frames_.slot()); }
    bool has_gpu_sort() const { return sort_.capacity() > 0; }
    VkBuffer sorted_records_buffer() const { return has_gpu_sort() ? sort_.sorted_records(frames_.slot()) : VK_NULL_HANDLE; }
    VkBuffer sort_control_buffer() const { return has_gpu_sort() ? sort_.control(frames_.slot()) : VK_NULL_HANDLE; }
    // The sort's record indices in drawing order (the sorted streams' lookup, binding 5).
    VkBuffer sort_order_buffer() const { return has_gpu_sort() ? sort_.values(frames_.slot()) : VK_NULL_HANDLE; }

    GpuTimings timings() const { return timings_; }
    gpu::UploadPath upload_path() const { return records_.path(); }
    uint32_t width() const { return target_.width(); }
    uint32_t height() const { return target_.height(); }
    uint32_t max_splats() const { return options_.max_splats; }
    SplatPath path() const { return splat_.path(); }
    bool anisotropic() const { return options_.anisotropic; }
    uint32_t sh_degree() const { return options_.sh_degree; }
    const std::array<Vec3f, 9>& environment_sh() const { return sh_; }
    const gpu::Context& context() const { return *ctx_; }

private:
    SplatRenderer() = default;
    // create() in steps: the frame ring and the record stream, the passes and the environment,
    // then the descriptor sets (sorted ones too), timers and per-slot state.
    core::Status create_streams();
    core::Status create_passes();
    core::Status create_sets();
    core::Status create_slot_state();  // per slot: timers, counters, pending flags
    core::Status collect_timings(uint32_t slot);
    // Frames drawn from the GPU sort's output, and the uniform sets that name it.
    static bool gpu_sorted(const SplatStyle& style);
    const gpu::UniformSets& frame_sets(const SplatStyle& style) const;
    // The records the splat pass draws this frame: the uploaded ones, or the GPU sort's.
    SplatSource splat_source(const FrameInputs& inputs, uint32_t count) const;

    gpu::Context* ctx_ = nullptr;
    RendererOptions options_;
    gpu::FrameRing frames_;
    gpu::UploadRing ring_;
    gpu::StreamBuffer records_;
    std::vector<gpu::Buffer> shapes_;  // one per slot; a token one when not anisotropic
    std::vector<gpu::Buffer> sh_rest_;  // one per slot; a token one without view-dependent colour
    std::vector<gpu::Buffer> texcoords_;  // one per slot; a token one without textured splats
    gpu::Texture white_;                   // binding 7's entries that no texture fills
    std::vector<gpu::Texture> textures_;   // set_textures()'s
    gpu::Buffer stream_identity_;       // 0, 1, 2, ...: where unsorted splats' stream entries are
    OffscreenTarget target_;
    SplatPass splat_;
    core::Status deferred_;  // the frame's first failure to prepare a style's pipelines
    bool prepared(const SplatStyle& style);  // false (and deferred_ set) when they could not be made
    GroundPass ground_;
    NormalisedBlend blend_;  // empty without options.normalised
    OccluderPass occluders_;  // empty without options.occluders
    gpu::Texture environment_;
    std::array<Vec3f, 9> sh_{};
    gpu::UniformSets uniforms_;  // one per frame in flight
    GpuSort sort_;
    gpu::UniformSets sorted_uniforms_;  // the same, with the sorted records at the storage binding
    std::vector<gpu::GpuTimer> timers_;
    std::vector<gpu::PipelineCounter> counters_;  // per slot
    std::vector<bool> slot_pending_;     // slot has a submitted frame whose timings are unread
    std::vector<bool> slot_read_back_;   // slot's frame copied its image out
    std::vector<GpuTimings> slot_cpu_;   // per slot, CPU-side figures measured while recording
    std::vector<SplatBounds> slot_bounds_;  // per slot, of the records uploaded for its frame
    VkRect2D normalised_area_{};            // the frame's sums and resolve: where its splats reach
    VkCommandBuffer cmd_ = VK_NULL_HANDLE;
    uint32_t last_slot_ = 0;
    bool any_frame_ = false;
    GpuTimings timings_;
};

} // namespace pbdsplat::render
