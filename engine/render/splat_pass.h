#pragma once
// The splat pass: one masked and shaded carrier per Gaussian record (paper sections 5.4-5.6),
// by one of three interchangeable paths that draw the same footprints (shaders/shared/
// splat_footprint.glsl): a geometry shader expanding points, a mesh shader expanding a fixed
// number of splats per workgroup, or vertex pulling (six vertices per splat) for devices with
// neither. Two footprints: the soft Gaussian (a depth-only visibility pass, then colour) and
// the paper's flat disc (one depth-tested, depth-writing pass).
#include <array>
#include <optional>

#include "gpu/device_handle.h"
#include "gpu/pipeline.h"
#include "render/frame_inputs.h"

namespace pbdsplat::render {

enum class SplatPath { geometry, mesh, vertex };
// The carrier each splat is drawn on: a quad, or an octagon that hugs the ellipse (17 % less
// area, three times the triangles). Vertex pulling always draws quads.
enum class SplatCarrier { quad, octagon };
inline constexpr core::EnumName<SplatPath> k_splat_path_names[] = {
    {SplatPath::geometry, "gs"}, {SplatPath::mesh, "mesh"}, {SplatPath::vertex, "vertex"}};
inline constexpr core::EnumName<SplatCarrier> k_splat_carrier_names[] = {{SplatCarrier::quad, "quad"}, {SplatCarrier::octagon, "octagon"}};
inline const char* splat_path_name(SplatPath p) { return core::name_of<SplatPath>(k_splat_path_names, p); }
// The fastest path the device has for these splats, by measurement: on CPU devices the geometry
// shader; on hardware vertex pulling for anisotropic splats (captures), else mesh, then
// geometry; vertex pulling where there is neither.
SplatPath best_splat_path(const gpu::DeviceCaps& caps, bool anisotropic = false);
// Why the device cannot run `path` (empty when it can).
std::string splat_path_unsupported(const gpu::DeviceCaps& caps, SplatPath path);

// The splats one draw reads: `count` records, or, after a GPU sort, as many as its control
// block says (`indirect`, SORT_CONTROL_* in gpu_types.h) out of at most `count`.
struct SplatSource {
    VkBuffer records = VK_NULL_HANDLE;
    uint32_t count = 0;
    VkBuffer indirect = VK_NULL_HANDLE;
};

class SplatPass {
public:
    // Fails with a clear reason when the device lacks what the path needs. `accumulation`: the
    // format of normalised blending's accumulation image (UNDEFINED: no normalised blending).
    static core::Result<SplatPass> create(const gpu::Context& ctx, VkFormat color, VkFormat depth, SplatPath path,
                                          SplatShading shading = SplatShading::fragment,
                                          SplatCarrier carrier = SplatCarrier::quad, bool anisotropic = false,
                                          uint32_t sh_degree = 0, VkFormat accumulation = VK_FORMAT_UNDEFINED,
                                          VkDescriptorSetLayout occluders = VK_NULL_HANDLE, uint32_t textures = 0);
    SplatPass() = default;

    SplatPath path() const { return path_; }
    SplatShading shading() const { return shading_; }
    SplatCarrier carrier() const { return carrier_; }
    // Reads each splat's axes from the shape stream (binding 3) instead of drawing it round.
    bool anisotropic() const { return anisotropic_; }
    // How many textures (bindings 6 and 7) the splats read under each pixel where they have one.
    uint32_t textures() const { return textures_; }
    VkDescriptorSetLayout set_layout() const { return set_layout_.get(); }
    // The Gaussian footprint under unsorted "over" draws the visibility pass first; sorted
    // orders, additive blending and the paper's disc draw one pass. `frame_set`'s storage
    // binding must hold `source.records`.
    // Normalised blending draws only the visibility pass here; record_accumulation() then adds
    // the front fragments into the accumulation image.
    void record(VkCommandBuffer cmd, const SplatStyle& style, VkDescriptorSet frame_set, const SplatSource& source) const;
    bool normalised() const { return variants_[size_t(Variant::accumulate)].described; }
    // Creates the pipelines that drawing `style` binds, the first time a style needs them (each
    // costs a shader compile: tens of milliseconds on a CPU device, so a scene pays only for
    // the ones it draws). Every record call needs it done for its style first.
    core::Status prepare(const SplatStyle& style);
    // How many pipeline variants have been made so far (of the ten a pass can draw with).
    size_t pipelines_made() const;
    // The paper's disc against mesh occluders (record() then draws nothing for it): set 1 holds
    // the occluders' distance image; needs the pass created with `occluders`.
    void record_paper_occluded(VkCommandBuffer cmd, const SplatStyle& style, VkDescriptorSet frame_set, const SplatSource& source,
                               VkDescriptorSet occluder_set) const;
    // `occluder_set` (set 1: the mesh occluders' distance image, render/occluder_pass.h): keep
    // only the fragments on the surface the mesh shows; needs the pass created with `occluders`.
    void record_accumulation(VkCommandBuffer cmd, VkDescriptorSet frame_set, const SplatSource& source,
                             VkDescriptorSet occluder_set = VK_NULL_HANDLE) const;

private:
    SplatPath path_ = SplatPath::geometry;
    SplatShading shading_ = SplatShading::fragment;
    SplatCarrier carrier_ = SplatCarrier::quad;
    bool anisotropic_ = false;
    uint32_t textures_ = 0;
    gpu::DescriptorSetLayout set_layout_;
    gpu::PipelineLayout layout_;
    gpu::PipelineLayout occluded_layout_;  // the frame set and the occluders' (set 1)
    // The pipeline variants, each described at creation and made by prepare() when first needed.
    enum class Variant : uint8_t {
        visibility,
        over,
        additive,
        paper_over,             // unsorted: writes depth, tests after the mask, opacity dithered
        paper_sorted,           // far to near: the same, opacity blended
        paper_additive,
        accumulate,             // normalised blending: weighted sums into the accumulation image
        accumulate_occluded,    // the same against mesh occluders
        paper_over_occluded,    // the paper's disc against them
        paper_sorted_occluded,
        count
    };
    struct LazyPipeline {
        gpu::GraphicsPipelineDesc desc;
        bool described = false;
        gpu::Pipeline pipeline;
    };
    std::array<LazyPipeline, size_t(Variant::count)> variants_;
    const gpu::Context* ctx_ = nullptr;
    void describe(Variant v, const gpu::GraphicsPipelineDesc& desc);
    core::Status make(Variant v);
    VkPipeline pipeline(Variant v) const;
    // What record() binds for `style`: the front pass (visibility or the paper's disc) and the
    // colour pass, either absent.
    static std::optional<Variant> front_variant(const SplatStyle& style);
    static std::optional<Variant> colour_variant(const SplatStyle& style);
    static Variant paper_occluded_variant(const SplatStyle& style);
    PFN_vkCmdDrawMeshTasksEXT draw_mesh_tasks_ = nullptr;
    PFN_vkCmdDrawMeshTasksIndirectEXT draw_mesh_tasks_indirect_ = nullptr;
    // The frame set (and the occluders' set 1, when given) and, on the geometry path, the records.
    void bind(VkCommandBuffer cmd, VkDescriptorSet frame_set, VkDescriptorSet occluder_set, const SplatSource& source) const;
    void draw(VkCommandBuffer cmd, const SplatSource& source) const;
    // create() in steps: the layouts every path shares, the front stages of the path, then
    // every pipeline variant's description.
    core::Status create_layouts(const gpu::Context& ctx, VkDescriptorSetLayout occluders);
    core::Status describe_front(const gpu::Context& ctx, gpu::GraphicsPipelineDesc& desc);
    void describe_pipelines(gpu::GraphicsPipelineDesc desc, uint32_t sh_degree, VkFormat accumulation);
    // The front stage of `desc` (of this pass's path) swapped for its occluder-culling variant.
    void cull_occluded(gpu::GraphicsPipelineDesc& desc) const;
    // The normalised blend's sums, from the Gaussian's "over" pipeline description.
    void describe_sums(gpu::GraphicsPipelineDesc sums, VkFormat accumulation);
};

} // namespace pbdsplat::render
