#pragma once
// Physical-device choice and the logical device, with the capabilities the renderer branches on.
#include <memory>
#include <string>

#include "gpu/instance.h"

namespace pbdsplat::gpu {

struct DeviceCaps {
    std::string name;
    std::string driver;         // driver name and info, e.g. "llvmpipe: Mesa 25.0.7"
    std::string type;           // "discrete", "integrated", "virtual", "cpu", "other"
    uint32_t api_version = 0;
    bool geometry_shader = false;
    bool mesh_shader = false;   // VK_EXT_mesh_shader with its meshShader feature
    bool timestamps = false;    // timestamp queries on the graphics queue
    float timestamp_period_ns = 0.0f;
    bool pipeline_statistics = false;  // the pipelineStatisticsQuery feature (gpu/pipeline_counter.h)
    uint32_t subgroup_size = 0;
    uint32_t max_image_dimension = 0;  // the largest image and framebuffer side
    // Device-local memory that the CPU can write directly (CPU or integrated devices): uploads
    // write in place instead of going through a staging copy.
    bool unified_memory = false;
};

std::string api_version_string(uint32_t v);

struct DeviceOptions {
    // Substring of the device name to pick (case-insensitive); empty: $PBDSPLAT_DEVICE, then the
    // best kind available (discrete, integrated, virtual, CPU).
    std::string name_filter;
    bool swapchain = false;  // enable VK_KHR_swapchain (needs an instance made with surface = true)
};

class Device {
public:
    static core::Result<std::unique_ptr<Device>> create(const Instance& instance, const DeviceOptions& options);
    ~Device();
    Device(const Device&) = delete;
    Device& operator=(const Device&) = delete;

    VkDevice handle() const { return device_; }
    VkPhysicalDevice physical() const { return physical_; }
    VkQueue queue() const { return queue_; }
    uint32_t queue_family() const { return queue_family_; }
    const DeviceCaps& caps() const { return caps_; }
    const VkPhysicalDeviceLimits& limits() const { return limits_; }
    const VkPhysicalDeviceMemoryProperties& memory_properties() const { return memory_; }

    void wait_idle() const;

private:
    Device() = default;
    VkPhysicalDevice physical_ = VK_NULL_HANDLE;
    VkDevice device_ = VK_NULL_HANDLE;
    VkQueue queue_ = VK_NULL_HANDLE;
    uint32_t queue_family_ = 0;
    DeviceCaps caps_;
    VkPhysicalDeviceLimits limits_{};
    VkPhysicalDeviceMemoryProperties memory_{};
};

} // namespace pbdsplat::gpu
