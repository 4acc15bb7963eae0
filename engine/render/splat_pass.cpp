#include "render/splat_pass.h"

#include "core/assert.h"
#include "gpu/uniform_sets.h"
#include "render/normalised_blend.h"
#include "splat/gaussian_record.h"

namespace pbdsplat::render {

namespace {
constexpr uint32_t k_splats_per_mesh_group = 32;  // SPLATS_PER_GROUP in splat.mesh
}

SplatPath best_splat_path(const gpu::DeviceCaps& caps, bool anisotropic) {
    // Measured (1280x720, docs/BENCHMARKS.md "The renderer"): on Lavapipe the mesh shader's
    // per-workgroup outputs cost about twice the geometry shader's whole pass, and vertex pulling
    // a tenth more, captures too, so a CPU device keeps the geometry shader. On an NVIDIA H200 the
    // three draw a scene's isotropic splats in the same time (20k: 0.82-0.84 ms), and the mesh
    // shader takes them; a capture's anisotropic ones (1M) take 12.0 ms pulled, 17.0 through the
    // geometry shader and 27.9 through the mesh shader, so hardware pulls those.
    if (caps.type == "cpu" && caps.geometry_shader) return SplatPath::geometry;
    if (anisotropic) return SplatPath::vertex;
    if (caps.mesh_shader) return SplatPath::mesh;
    if (caps.geometry_shader) return SplatPath::geometry;
    return SplatPath::vertex;
}

std::string splat_path_unsupported(const gpu::DeviceCaps& caps, SplatPath path) {
    if (path == SplatPath::mesh && !caps.mesh_shader)
        return "device '" + caps.name + "' has no VK_EXT_mesh_shader (Lavapipe has it from Mesa 24; use --path gs or vertex)";
    if (path == SplatPath::geometry && !caps.geometry_shader)
        return "device '" + caps.name + "' has no geometry shaders (use --path vertex)";
    return {};
}

core::Result<SplatPass> SplatPass::create(const gpu::Context& ctx, VkFormat color, VkFormat depth, SplatPath path,
                                          SplatShading shading, SplatCarrier carrier, bool anisotropic, uint32_t sh_degree,
                                          VkFormat accumulation, VkDescriptorSetLayout occluders, uint32_t textures) {
    if (sh_degree > 3) return core::make_error("spherical-harmonic degree " + std::to_string(sh_degree) + " is not 0 to 3");
    if (const std::string why = splat_path_unsupported(ctx.caps(), path); !why.empty()) return core::make_error(why);
    SplatPass p;
    p.ctx_ = &ctx;
    p.path_ = path;
    p.shading_ = shading;
    p.carrier_ = path == SplatPath::vertex ? SplatCarrier::quad : carrier;
    p.anisotropic_ = anisotropic;
    if (textures > SPLAT_MAX_TEXTURES)
        return core::make_error(std::to_string(textures) + " textures; splats read at most " + std::to_string(SPLAT_MAX_TEXTURES));
    p.textures_ = textures;
    PBDSPLAT_TRY(p.create_layouts(ctx, occluders));
    gpu::GraphicsPipelineDesc desc;
    PBDSPLAT_TRY(p.describe_front(ctx, desc));
    desc.color_format = color;
    desc.depth_format = depth;
    desc.layout = p.layout_.get();
    p.describe_pipelines(std::move(desc), sh_degree, accumulation);
    return p;
}

core::Status SplatPass::create_layouts(const gpu::Context& ctx, VkDescriptorSetLayout occluders) {
    const VkShaderStageFlags front = path_ == SplatPath::geometry ? VK_SHADER_STAGE_GEOMETRY_BIT
                                     : path_ == SplatPath::mesh  ? VK_SHADER_STAGE_MESH_BIT_EXT
                                                                 : VK_SHADER_STAGE_VERTEX_BIT;
    gpu::FrameSetStages stages;
    stages.uniforms = front | VK_SHADER_STAGE_FRAGMENT_BIT | VK_SHADER_STAGE_VERTEX_BIT;  // vertex: the ground pass
    stages.texture = VK_SHADER_STAGE_FRAGMENT_BIT | front;  // the front stage shades per corner
    // The geometry path takes records as vertex attributes; its binding 2 is declared only so
    // that every path shares one set shape.
    stages.storage = path_ == SplatPath::geometry ? VkShaderStageFlags(VK_SHADER_STAGE_VERTEX_BIT) : front;
    stages.shapes = front;  // every front stage declares the shape stream; anisotropic ones read it
    stages.sh = front;      // the same for view-dependent colour
    stages.order = front;   // and for where a sorted splat's entries in those two are
    stages.texcoords = front;  // and for textured splats' coordinates, and their textures
    stages.textures = VK_SHADER_STAGE_FRAGMENT_BIT;
    stages.texture_count = SPLAT_MAX_TEXTURES;
    auto set_layout = gpu::create_frame_layout(ctx, stages);
    if (!set_layout.ok()) return set_layout.error();
    set_layout_ = std::move(set_layout).value();
    const VkPushConstantRange count_range{VK_SHADER_STAGE_MESH_BIT_EXT, 0, sizeof(uint32_t)};
    auto pipeline_layout = gpu::create_pipeline_layout(ctx, set_layout_.get(), path_ == SplatPath::mesh ? count_range : VkPushConstantRange{});
    if (!pipeline_layout.ok()) return pipeline_layout.error();
    layout_ = std::move(pipeline_layout).value();
    if (occluders) {
        const VkDescriptorSetLayout sets[2] = {set_layout_.get(), occluders};
        auto occluded = gpu::create_pipeline_layout(ctx, sets, path_ == SplatPath::mesh ? count_range : VkPushConstantRange{});
        if (!occluded.ok()) return occluded.error();
        occluded_layout_ = std::move(occluded).value();
    }
    return core::Status::success();
}

core::Status SplatPass::describe_front(const gpu::Context& ctx, gpu::GraphicsPipelineDesc& desc) {
    switch (path_) {
    case SplatPath::geometry:
        desc.stages = {{VK_SHADER_STAGE_VERTEX_BIT, "splat.vert"}, {VK_SHADER_STAGE_GEOMETRY_BIT, "splat.geom"}};
        desc.bindings = {{0, sizeof(splat::GaussianRecord), VK_VERTEX_INPUT_RATE_VERTEX}};
        desc.attributes = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, SPLAT_OFFSET_POSITION},
                           {1, 0, VK_FORMAT_R16G16_SNORM, SPLAT_OFFSET_NORMAL},
                           {2, 0, VK_FORMAT_R8G8B8A8_UNORM, SPLAT_OFFSET_COLOR},
                           {3, 0, VK_FORMAT_R16G16_SFLOAT, SPLAT_OFFSET_SCALE_OPACITY},
                           {4, 0, VK_FORMAT_R16G16B16A16_SFLOAT, SPLAT_OFFSET_CURVATURE}};
        desc.topology = VK_PRIMITIVE_TOPOLOGY_POINT_LIST;
        break;
    case SplatPath::mesh:
        desc.stages = {{VK_SHADER_STAGE_MESH_BIT_EXT, "splat.mesh"}};
        draw_mesh_tasks_ = reinterpret_cast<PFN_vkCmdDrawMeshTasksEXT>(vkGetDeviceProcAddr(ctx.vk(), "vkCmdDrawMeshTasksEXT"));
        draw_mesh_tasks_indirect_ = reinterpret_cast<PFN_vkCmdDrawMeshTasksIndirectEXT>(vkGetDeviceProcAddr(ctx.vk(), "vkCmdDrawMeshTasksIndirectEXT"));
        if (!draw_mesh_tasks_ || !draw_mesh_tasks_indirect_)
            return core::make_error("vkCmdDrawMeshTasks(Indirect)EXT is missing although the device reports VK_EXT_mesh_shader");
        break;
    case SplatPath::vertex:
        desc.stages = {{VK_SHADER_STAGE_VERTEX_BIT, "splat_pull.vert"}};
        desc.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
        break;
    }
    desc.stages.push_back({VK_SHADER_STAGE_FRAGMENT_BIT, "splat_visibility.frag"});
    return core::Status::success();
}

void SplatPass::describe(Variant v, const gpu::GraphicsPipelineDesc& desc) {
    LazyPipeline& lazy = variants_[size_t(v)];
    lazy.desc = desc;
    if (textures_ > 0) {
        lazy.desc.specialization.resize(9, 0u);
        lazy.desc.specialization[8] = textures_;  // k_texture_count
    }
    lazy.described = true;
}

core::Status SplatPass::make(Variant v) {
    LazyPipeline& lazy = variants_[size_t(v)];
    if (lazy.pipeline) return core::Status::success();
    PBDSPLAT_ASSERT(lazy.described, "SplatPass: a pipeline variant this pass was not created for");
    auto made = gpu::create_graphics_pipeline(*ctx_, lazy.desc);
    if (!made.ok()) return made.error();
    lazy.pipeline = std::move(made).value();
    return core::Status::success();
}

size_t SplatPass::pipelines_made() const {
    size_t n = 0;
    for (const LazyPipeline& lazy : variants_) n += lazy.pipeline ? 1 : 0;
    return n;
}

VkPipeline SplatPass::pipeline(Variant v) const {
    const LazyPipeline& lazy = variants_[size_t(v)];
    PBDSPLAT_ASSERT(lazy.pipeline, "SplatPass: draw a style only after prepare(style)");
    return lazy.pipeline.get();
}

std::optional<SplatPass::Variant> SplatPass::front_variant(const SplatStyle& style) {
    const bool additive = style.blend == Blend::additive, normalised = style.blend == Blend::normalised;
    if (style.footprint == Footprint::paper) {
        if (occluded_style(style)) return std::nullopt;  // record_paper_occluded()
        return additive ? Variant::paper_additive : style.order == SplatOrder::unsorted ? Variant::paper_over : Variant::paper_sorted;
    }
    // Mesh occluders lay down the visibility depth in their own pass (render/occluder_pass.h).
    if (!additive && ((normalised && !style.mesh_occluders) || (!normalised && style.order == SplatOrder::unsorted)))
        return Variant::visibility;
    return std::nullopt;
}

std::optional<SplatPass::Variant> SplatPass::colour_variant(const SplatStyle& style) {
    // The paper's disc is one pass; normalised sums follow in their own (record_accumulation).
    if (style.footprint == Footprint::paper || style.blend == Blend::normalised) return std::nullopt;
    return style.blend == Blend::additive ? Variant::additive : Variant::over;
}

SplatPass::Variant SplatPass::paper_occluded_variant(const SplatStyle& style) {
    return style.order == SplatOrder::unsorted ? Variant::paper_over_occluded : Variant::paper_sorted_occluded;
}

core::Status SplatPass::prepare(const SplatStyle& style) {
    if (const auto v = front_variant(style)) PBDSPLAT_TRY(make(*v));
    if (const auto v = colour_variant(style)) PBDSPLAT_TRY(make(*v));
    const bool occluded = occluded_style(style) && occluded_layout_;
    if (style.footprint == Footprint::paper && occluded) PBDSPLAT_TRY(make(paper_occluded_variant(style)));
    if (style.blend == Blend::normalised && normalised())
        PBDSPLAT_TRY(make(occluded ? Variant::accumulate_occluded : Variant::accumulate));
    return core::Status::success();
}

void SplatPass::cull_occluded(gpu::GraphicsPipelineDesc& desc) const {
    // The geometry and mesh paths' front stages drop (or leave empty) the carriers the occluders
    // hide whole, once a splat. Vertex pulling does not: each of a splat's six vertices would
    // repeat the test, and on Lavapipe bunny_cut's frame took 158 ms instead of 110 with it.
    switch (path_) {
    case SplatPath::geometry: desc.stages[1].second = "splat_occluded.geom"; break;
    case SplatPath::mesh: desc.stages[0].second = "splat_occluded.mesh"; break;
    case SplatPath::vertex: break;
    }
}

void SplatPass::describe_sums(gpu::GraphicsPipelineDesc sums, VkFormat accumulation) {
    // The same fragments as the Gaussian's, summed as weights and weighted colours into the float image.
    sums.stages.back().second = "splat_accumulate.frag";
    sums.color_format = accumulation;
    sums.color_count = k_sum_layers;
    sums.specialization.resize(8, 0u);
    sums.specialization[7] = 1u;  // k_opaque_surface: what shows is the surface, lit from the seen side
    describe(Variant::accumulate, sums);
    if (!occluded_layout_) return;
    sums.stages.back().second = "splat_accumulate_occluded.frag";
    cull_occluded(sums);
    sums.layout = occluded_layout_.get();
    describe(Variant::accumulate_occluded, sums);
}

void SplatPass::describe_pipelines(gpu::GraphicsPipelineDesc desc, uint32_t sh_degree, VkFormat accumulation) {
    const uint32_t per_corner = shading_ == SplatShading::corner ? 1u : 0u;
    const uint32_t octagon = carrier_ == SplatCarrier::octagon ? 1u : 0u;
    const uint32_t aniso = anisotropic_ ? 1u : 0u;
    desc.color_write = false;
    // k_visibility_pass, k_shade_per_corner, k_footprint, k_octagon, k_footprint_dither, k_anisotropic,
    // k_sh_degree (and k_opaque_surface, 0 unless given)
    desc.specialization = {1u, per_corner, SPLAT_FOOTPRINT_GAUSSIAN, octagon, 0u, aniso, sh_degree};
    describe(Variant::visibility, desc);

    desc.stages.back().second = "splat.frag";
    desc.color_write = true;
    desc.specialization = {0u, per_corner, SPLAT_FOOTPRINT_GAUSSIAN, octagon, 0u, aniso, sh_degree};
    desc.depth_write = false;
    desc.blend = gpu::BlendMode::over_premultiplied;
    describe(Variant::over, desc);
    // Additive splats do not occlude one another: order does not matter, no visibility pass.
    desc.blend = gpu::BlendMode::additive;
    describe(Variant::additive, desc);
    if (accumulation != VK_FORMAT_UNDEFINED) describe_sums(desc, accumulation);

    // The paper's disc: additive blending needs no depth; "over" writes it, so the nearest disc
    // wins each pixel whatever the draw order (its mask must run before the test).
    desc.specialization = {0u, per_corner, SPLAT_FOOTPRINT_PAPER, octagon, 0u, aniso, sh_degree};
    describe(Variant::paper_additive, desc);
    desc.stages.back().second = "splat_paper.frag";
    desc.blend = gpu::BlendMode::over_premultiplied;
    desc.depth_write = true;
    // Sorted far to near, the flat alpha blends over what lies behind, as the paper composites.
    describe(Variant::paper_sorted, desc);
    if (occluded_layout_) {
        gpu::GraphicsPipelineDesc occluded = desc;
        occluded.stages.back().second = "splat_paper_occluded.frag";
        cull_occluded(occluded);
        occluded.layout = occluded_layout_.get();
        describe(Variant::paper_sorted_occluded, occluded);
        occluded.specialization[4] = 1u;
        describe(Variant::paper_over_occluded, occluded);
    }
    desc.specialization[4] = 1u;  // k_footprint_dither: unsorted, opacity becomes coverage
    describe(Variant::paper_over, desc);
}

void SplatPass::draw(VkCommandBuffer cmd, const SplatSource& s) const {
    const uint32_t count = s.count;
    if (s.indirect) {
        // The sort padded its output to whole mesh workgroups with zero-scale records, so the
        // mesh shader may read up to the padded capacity.
        const uint32_t padded = (count + SORT_MESH_GROUP - 1) / SORT_MESH_GROUP * SORT_MESH_GROUP;
        constexpr VkDeviceSize word = 4;
        switch (path_) {
        case SplatPath::geometry: vkCmdDrawIndirect(cmd, s.indirect, SORT_CONTROL_DRAW * word, 1, 0); break;
        case SplatPath::vertex: vkCmdDrawIndirect(cmd, s.indirect, SORT_CONTROL_DRAW_PULL * word, 1, 0); break;
        case SplatPath::mesh:
            vkCmdPushConstants(cmd, layout_.get(), VK_SHADER_STAGE_MESH_BIT_EXT, 0, sizeof(uint32_t), &padded);
            draw_mesh_tasks_indirect_(cmd, s.indirect, SORT_CONTROL_MESH * word, 1, 0);
            break;
        }
        return;
    }
    switch (path_) {
    case SplatPath::geometry: vkCmdDraw(cmd, count, 1, 0, 0); break;
    case SplatPath::vertex: vkCmdDraw(cmd, 6 * count, 1, 0, 0); break;
    case SplatPath::mesh:
        vkCmdPushConstants(cmd, layout_.get(), VK_SHADER_STAGE_MESH_BIT_EXT, 0, sizeof(uint32_t), &count);
        draw_mesh_tasks_(cmd, (count + k_splats_per_mesh_group - 1) / k_splats_per_mesh_group, 1, 1);
        break;
    }
}

void SplatPass::bind(VkCommandBuffer cmd, VkDescriptorSet frame_set, VkDescriptorSet occluder_set, const SplatSource& source) const {
    const VkDescriptorSet sets[2] = {frame_set, occluder_set};
    const VkPipelineLayout layout = occluder_set ? occluded_layout_.get() : layout_.get();
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout, 0, occluder_set ? 2 : 1, sets, 0, nullptr);
    if (path_ == SplatPath::geometry) {
        const VkDeviceSize offset = 0;
        vkCmdBindVertexBuffers(cmd, 0, 1, &source.records, &offset);
    }
}

void SplatPass::record(VkCommandBuffer cmd, const SplatStyle& style, VkDescriptorSet frame_set,
                       const SplatSource& source) const {
    if (source.count == 0) return;
    const auto front = front_variant(style), colour = colour_variant(style);
    if (!front && !colour) return;  // record_paper_occluded() or record_accumulation()
    bind(cmd, frame_set, VK_NULL_HANDLE, source);
    for (const auto& v : {front, colour}) {
        if (!v) continue;
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline(*v));
        draw(cmd, source);
    }
}

void SplatPass::record_paper_occluded(VkCommandBuffer cmd, const SplatStyle& style, VkDescriptorSet frame_set,
                                      const SplatSource& source, VkDescriptorSet occluder_set) const {
    PBDSPLAT_ASSERT(occluded_layout_, "SplatPass::record_paper_occluded: create the pass with the occluders' set layout");
    if (source.count == 0) return;
    bind(cmd, frame_set, occluder_set, source);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline(paper_occluded_variant(style)));
    draw(cmd, source);
}

void SplatPass::record_accumulation(VkCommandBuffer cmd, VkDescriptorSet frame_set, const SplatSource& source,
                                    VkDescriptorSet occluder_set) const {
    PBDSPLAT_ASSERT(normalised(), "SplatPass::record_accumulation: create the pass with an accumulation format");
    PBDSPLAT_ASSERT(!occluder_set || variants_[size_t(Variant::accumulate_occluded)].described,
                    "SplatPass::record_accumulation with occluders: create the pass with the occluders' set layout");
    if (source.count == 0) return;
    bind(cmd, frame_set, occluder_set, source);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline(occluder_set ? Variant::accumulate_occluded : Variant::accumulate));
    draw(cmd, source);
}

} // namespace pbdsplat::render
