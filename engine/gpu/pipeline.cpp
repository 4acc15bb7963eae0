#include "gpu/pipeline.h"

#include <array>

#include "embedded_shaders.h"

namespace pbdsplat::gpu {

core::Result<ShaderModule> load_shader(const Context& ctx, const std::string& name) {
    const auto words = shaders::find(name);
    if (words.empty()) return core::make_error("shader '" + name + "' is not embedded in this build");
    VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    info.codeSize = words.size() * sizeof(uint32_t);
    info.pCode = words.data();
    VkShaderModule m = VK_NULL_HANDLE;
    PBDSPLAT_VK_TRY(vkCreateShaderModule(ctx.vk(), &info, nullptr, &m));
    return ShaderModule(ctx.vk(), m);
}

namespace {
// The shader stages of `desc`, specialised by `spec` (which must outlive the pipeline's creation).
core::Status load_stages(const Context& ctx, const GraphicsPipelineDesc& desc, const VkSpecializationInfo& spec,
                         std::vector<ShaderModule>& modules, std::vector<VkPipelineShaderStageCreateInfo>& stages) {
    for (const auto& [stage, name] : desc.stages) {
        auto m = load_shader(ctx, name);
        if (!m.ok()) return m.error();
        modules.push_back(std::move(m).value());
        VkPipelineShaderStageCreateInfo s{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
        s.stage = stage;
        s.module = modules.back().get();
        s.pName = "main";
        if (!desc.specialization.empty()) s.pSpecializationInfo = &spec;
        stages.push_back(s);
    }
    return core::Status::success();
}

// The fixed-function state of a graphics pipeline in one object that neither copies nor moves,
// so the pointers between its parts stay valid until the pipeline is made.
struct FixedState {
    VkPipelineVertexInputStateCreateInfo vertex{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
    VkPipelineInputAssemblyStateCreateInfo assembly{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
    VkPipelineViewportStateCreateInfo viewport{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
    VkPipelineRasterizationStateCreateInfo raster{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
    VkPipelineMultisampleStateCreateInfo multisample{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
    VkPipelineDepthStencilStateCreateInfo depth{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
    VkPipelineColorBlendAttachmentState attachment{};
    std::array<VkPipelineColorBlendAttachmentState, 4> attachments{};
    std::array<VkFormat, 4> formats{};
    VkPipelineColorBlendStateCreateInfo blend{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
    VkDynamicState dyn[2] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
    VkPipelineDynamicStateCreateInfo dynamic{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
    VkPipelineRenderingCreateInfo rendering{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};

    explicit FixedState(const GraphicsPipelineDesc& desc) {
        vertex.vertexBindingDescriptionCount = uint32_t(desc.bindings.size());
        vertex.pVertexBindingDescriptions = desc.bindings.data();
        vertex.vertexAttributeDescriptionCount = uint32_t(desc.attributes.size());
        vertex.pVertexAttributeDescriptions = desc.attributes.data();
        assembly.topology = desc.topology;
        viewport.viewportCount = 1;
        viewport.scissorCount = 1;
        raster.polygonMode = VK_POLYGON_MODE_FILL;
        raster.cullMode = desc.cull;
        raster.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
        raster.lineWidth = 1.0f;
        multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
        depth.depthTestEnable = desc.depth_test ? VK_TRUE : VK_FALSE;
        depth.depthWriteEnable = desc.depth_write ? VK_TRUE : VK_FALSE;
        depth.depthCompareOp = VK_COMPARE_OP_LESS_OR_EQUAL;
        attachment.colorWriteMask = desc.color_write ? VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT | VK_COLOR_COMPONENT_B_BIT |
                                                           VK_COLOR_COMPONENT_A_BIT
                                                     : 0;
        if (desc.blend != BlendMode::none) {
            attachment.blendEnable = VK_TRUE;
            attachment.colorBlendOp = attachment.alphaBlendOp = VK_BLEND_OP_ADD;
            attachment.srcColorBlendFactor = attachment.srcAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
            attachment.dstColorBlendFactor = attachment.dstAlphaBlendFactor =
                desc.blend == BlendMode::additive ? VK_BLEND_FACTOR_ONE : VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA;
        }
        attachments.fill(attachment);
        formats.fill(desc.color_format);
        blend.attachmentCount = desc.color_count;
        blend.pAttachments = attachments.data();
        dynamic.dynamicStateCount = 2;
        dynamic.pDynamicStates = dyn;
        rendering.colorAttachmentCount = desc.color_count;
        rendering.pColorAttachmentFormats = formats.data();
        rendering.depthAttachmentFormat = desc.depth_format;
    }
    FixedState(const FixedState&) = delete;
    FixedState& operator=(const FixedState&) = delete;
};
} // namespace

core::Result<Pipeline> create_graphics_pipeline(const Context& ctx, const GraphicsPipelineDesc& desc) {
    PBDSPLAT_ASSERT(desc.color_count >= 1 && desc.color_count <= 4, "GraphicsPipelineDesc::color_count: give 1 to 4 attachments");
    std::vector<VkSpecializationMapEntry> spec_entries;
    for (uint32_t i = 0; i < desc.specialization.size(); ++i) spec_entries.push_back({i, uint32_t(i * sizeof(uint32_t)), sizeof(uint32_t)});
    const VkSpecializationInfo spec{uint32_t(spec_entries.size()), spec_entries.data(), desc.specialization.size() * sizeof(uint32_t),
                                    desc.specialization.data()};
    std::vector<ShaderModule> modules;
    std::vector<VkPipelineShaderStageCreateInfo> stages;
    PBDSPLAT_TRY(load_stages(ctx, desc, spec, modules, stages));
    const FixedState fixed(desc);
    VkGraphicsPipelineCreateInfo info{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
    info.pNext = &fixed.rendering;
    info.stageCount = uint32_t(stages.size());
    info.pStages = stages.data();
    info.pVertexInputState = &fixed.vertex;
    info.pInputAssemblyState = &fixed.assembly;
    info.pViewportState = &fixed.viewport;
    info.pRasterizationState = &fixed.raster;
    info.pMultisampleState = &fixed.multisample;
    info.pDepthStencilState = &fixed.depth;
    info.pColorBlendState = &fixed.blend;
    info.pDynamicState = &fixed.dynamic;
    info.layout = desc.layout;
    VkPipeline p = VK_NULL_HANDLE;
    PBDSPLAT_VK_TRY(vkCreateGraphicsPipelines(ctx.vk(), VK_NULL_HANDLE, 1, &info, nullptr, &p));
    return Pipeline(ctx.vk(), p);
}

core::Result<PipelineLayout> create_pipeline_layout(const Context& ctx, VkDescriptorSetLayout set_layout,
                                                    VkPushConstantRange push) {
    return create_pipeline_layout(ctx, std::span<const VkDescriptorSetLayout>(&set_layout, 1), push);
}

core::Result<PipelineLayout> create_pipeline_layout(const Context& ctx, std::span<const VkDescriptorSetLayout> set_layouts,
                                                    VkPushConstantRange push) {
    VkPipelineLayoutCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    info.setLayoutCount = uint32_t(set_layouts.size());
    info.pSetLayouts = set_layouts.data();
    info.pushConstantRangeCount = push.size > 0 ? 1 : 0;
    info.pPushConstantRanges = &push;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    PBDSPLAT_VK_TRY(vkCreatePipelineLayout(ctx.vk(), &info, nullptr, &layout));
    return PipelineLayout(ctx.vk(), layout);
}

core::Result<Pipeline> create_compute_pipeline(const Context& ctx, const std::string& shader, VkPipelineLayout layout) {
    auto module = load_shader(ctx, shader);
    if (!module.ok()) return module.error();
    VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    info.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
    info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    info.stage.module = module->get();
    info.stage.pName = "main";
    info.layout = layout;
    VkPipeline p = VK_NULL_HANDLE;
    PBDSPLAT_VK_TRY(vkCreateComputePipelines(ctx.vk(), VK_NULL_HANDLE, 1, &info, nullptr, &p));
    return Pipeline(ctx.vk(), p);
}

} // namespace pbdsplat::gpu
