#pragma once
// Shader modules from the embedded SPIR-V, and a small description of a graphics pipeline for
// dynamic rendering (no render-pass objects).
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gpu/context.h"
#include "gpu/device_handle.h"

namespace pbdsplat::gpu {

core::Result<ShaderModule> load_shader(const Context& ctx, const std::string& name);

enum class BlendMode { over_premultiplied, additive, none };

struct GraphicsPipelineDesc {
    std::vector<std::pair<VkShaderStageFlagBits, std::string>> stages;  // stage, embedded shader name
    std::vector<VkVertexInputBindingDescription> bindings;
    std::vector<VkVertexInputAttributeDescription> attributes;
    VkPrimitiveTopology topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
    VkFormat color_format = VK_FORMAT_R8G8B8A8_UNORM;
    uint32_t color_count = 1;  // colour attachments, all of color_format, written and blended alike (at most 4)
    VkFormat depth_format = VK_FORMAT_D32_SFLOAT;
    bool depth_test = true;
    bool depth_write = true;
    bool color_write = true;
    // Values of specialization constants 0, 1, ... (bools or uints), given to every stage.
    std::vector<uint32_t> specialization;
    VkCullModeFlags cull = VK_CULL_MODE_NONE;
    BlendMode blend = BlendMode::none;
    VkPipelineLayout layout = VK_NULL_HANDLE;
};

core::Result<Pipeline> create_graphics_pipeline(const Context& ctx, const GraphicsPipelineDesc& desc);
// One descriptor set layout and at most one push-constant range (size 0: none).
core::Result<PipelineLayout> create_pipeline_layout(const Context& ctx, VkDescriptorSetLayout set_layout,
                                                    VkPushConstantRange push = {});
// Sets 0, 1, ... in order (none: push constants alone).
core::Result<PipelineLayout> create_pipeline_layout(const Context& ctx, std::span<const VkDescriptorSetLayout> set_layouts,
                                                    VkPushConstantRange push = {});
core::Result<Pipeline> create_compute_pipeline(const Context& ctx, const std::string& shader, VkPipelineLayout layout);

} // namespace pbdsplat::gpu
