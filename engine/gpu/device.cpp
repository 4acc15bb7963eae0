#include "gpu/device.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <cstring>
#include <vector>

namespace pbdsplat::gpu {
namespace {

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

const char* type_name(VkPhysicalDeviceType t) {
    switch (t) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete";
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated";
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual";
        case VK_PHYSICAL_DEVICE_TYPE_CPU: return "cpu";
        default: return "other";
    }
}

int type_rank(VkPhysicalDeviceType t) {
    switch (t) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 4;
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 3;
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
        case VK_PHYSICAL_DEVICE_TYPE_CPU: return 1;
        default: return 0;
    }
}

bool has_device_extension(VkPhysicalDevice pd, const char* name) {
    uint32_t n = 0;
    vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, nullptr);
    std::vector<VkExtensionProperties> all(n);
    vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, all.data());
    for (const auto& e : all)
        if (std::strcmp(e.extensionName, name) == 0) return true;
    return false;
}

// The first queue family that does graphics and compute, or -1.
int graphics_family(VkPhysicalDevice pd) {
    uint32_t n = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, nullptr);
    std::vector<VkQueueFamilyProperties> fam(n);
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, fam.data());
    for (uint32_t i = 0; i < n; ++i)
        if ((fam[i].queueFlags & VK_QUEUE_GRAPHICS_BIT) && (fam[i].queueFlags & VK_QUEUE_COMPUTE_BIT)) return int(i);
    return -1;
}

DeviceCaps query_caps(VkPhysicalDevice pd, uint32_t family) {
    DeviceCaps c;
    VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
    VkPhysicalDeviceSubgroupProperties subgroup{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
    subgroup.pNext = &driver;
    VkPhysicalDeviceProperties2 props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    props.pNext = &subgroup;
    vkGetPhysicalDeviceProperties2(pd, &props);

    c.name = props.properties.deviceName;
    c.driver = std::string(driver.driverName) + ": " + driver.driverInfo;
    c.type = type_name(props.properties.deviceType);
    c.api_version = props.properties.apiVersion;
    c.subgroup_size = subgroup.subgroupSize;

    VkPhysicalDeviceMeshShaderFeaturesEXT mesh{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MESH_SHADER_FEATURES_EXT};
    VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    const bool mesh_ext = has_device_extension(pd, VK_EXT_MESH_SHADER_EXTENSION_NAME);
    if (mesh_ext) features.pNext = &mesh;
    vkGetPhysicalDeviceFeatures2(pd, &features);
    c.geometry_shader = features.features.geometryShader == VK_TRUE;
    c.pipeline_statistics = features.features.pipelineStatisticsQuery == VK_TRUE;
    c.mesh_shader = mesh_ext && mesh.meshShader == VK_TRUE;

    uint32_t n = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, nullptr);
    std::vector<VkQueueFamilyProperties> fam(n);
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, fam.data());
    c.timestamps = props.properties.limits.timestampPeriod > 0.0f && fam[family].timestampValidBits > 0;
    c.timestamp_period_ns = props.properties.limits.timestampPeriod;
    c.max_image_dimension = std::min(props.properties.limits.maxImageDimension2D,
                                     std::min(props.properties.limits.maxFramebufferWidth, props.properties.limits.maxFramebufferHeight));

    VkPhysicalDeviceMemoryProperties mem;
    vkGetPhysicalDeviceMemoryProperties(pd, &mem);
    const VkMemoryPropertyFlags direct = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT | VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT |
                                         VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    bool has_direct = false;
    for (uint32_t i = 0; i < mem.memoryTypeCount; ++i)
        has_direct = has_direct || (mem.memoryTypes[i].propertyFlags & direct) == direct;
    // A discrete GPU may expose a host-visible window on its memory (resizable BAR), but CPU
    // writes then cross the bus one by one: a staged copy stays faster there.
    c.unified_memory = has_direct && (props.properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU ||
                                      props.properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU);
    return c;
}

} // namespace

std::string api_version_string(uint32_t v) {
    return std::to_string(VK_API_VERSION_MAJOR(v)) + "." + std::to_string(VK_API_VERSION_MINOR(v)) + "." +
           std::to_string(VK_API_VERSION_PATCH(v));
}

namespace {
// The most capable Vulkan 1.3 device with a graphics queue (a discrete GPU before an integrated
// one before a CPU), among those whose name holds the filter (option, else PBDSPLAT_DEVICE).
core::Result<VkPhysicalDevice> pick_device(const Instance& instance, const DeviceOptions& options) {
    uint32_t n = 0;
    vkEnumeratePhysicalDevices(instance.handle(), &n, nullptr);
    std::vector<VkPhysicalDevice> all(n);
    vkEnumeratePhysicalDevices(instance.handle(), &n, all.data());
    if (all.empty())
        return core::make_error("no Vulkan device found: install Mesa's Lavapipe (apt-get install mesa-vulkan-drivers, "
                                "or run tools/setup)");

    std::string filter = options.name_filter;
    if (filter.empty())
        if (const char* env = std::getenv("PBDSPLAT_DEVICE")) filter = env;
    filter = lower(filter);

    VkPhysicalDevice best = VK_NULL_HANDLE;
    int best_rank = -1;
    std::string seen;
    for (VkPhysicalDevice pd : all) {
        VkPhysicalDeviceProperties p;
        vkGetPhysicalDeviceProperties(pd, &p);
        seen += std::string(seen.empty() ? "" : ", ") + p.deviceName;
        if (p.apiVersion < VK_API_VERSION_1_3 || graphics_family(pd) < 0) continue;
        if (!filter.empty() && lower(p.deviceName).find(filter) == std::string::npos) continue;
        const int rank = type_rank(p.deviceType);
        if (rank > best_rank) best = pd, best_rank = rank;
    }
    if (best == VK_NULL_HANDLE) {
        if (!filter.empty())
            return core::make_error("no Vulkan 1.3 device with graphics matches the name '" + filter + "' (seen: " + seen +
                                    "); fix PBDSPLAT_DEVICE or --device");
        return core::make_error("no Vulkan 1.3 device with a graphics queue (seen: " + seen + ")");
    }
    return best;
}
} // namespace

core::Result<std::unique_ptr<Device>> Device::create(const Instance& instance, const DeviceOptions& options) {
    auto picked = pick_device(instance, options);
    if (!picked.ok()) return picked.error();
    const VkPhysicalDevice best = picked.value();
    auto dev = std::unique_ptr<Device>(new Device());
    dev->physical_ = best;
    dev->queue_family_ = uint32_t(graphics_family(best));
    dev->caps_ = query_caps(best, dev->queue_family_);
    VkPhysicalDeviceProperties p;
    vkGetPhysicalDeviceProperties(best, &p);
    dev->limits_ = p.limits;
    vkGetPhysicalDeviceMemoryProperties(best, &dev->memory_);

    const float priority = 1.0f;
    VkDeviceQueueCreateInfo queue{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    queue.queueFamilyIndex = dev->queue_family_;
    queue.queueCount = 1;
    queue.pQueuePriorities = &priority;

    VkPhysicalDeviceMeshShaderFeaturesEXT mesh{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MESH_SHADER_FEATURES_EXT};
    mesh.meshShader = VK_TRUE;
    VkPhysicalDeviceVulkan13Features v13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
    v13.dynamicRendering = VK_TRUE;
    v13.synchronization2 = VK_TRUE;
    v13.maintenance4 = VK_TRUE;
    VkPhysicalDeviceVulkan12Features v12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    v12.pNext = &v13;
    v12.hostQueryReset = VK_TRUE;
    VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    features.pNext = &v12;
    features.features.geometryShader = dev->caps_.geometry_shader ? VK_TRUE : VK_FALSE;
    features.features.pipelineStatisticsQuery = dev->caps_.pipeline_statistics ? VK_TRUE : VK_FALSE;

    std::vector<const char*> extensions;
    if (dev->caps_.mesh_shader) {
        extensions.push_back(VK_EXT_MESH_SHADER_EXTENSION_NAME);
        v13.pNext = &mesh;
    }
    if (options.swapchain) {
        if (!has_device_extension(best, VK_KHR_SWAPCHAIN_EXTENSION_NAME))
            return core::make_error("device '" + dev->caps_.name + "' cannot present to a window (no VK_KHR_swapchain)");
        extensions.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
    }

    VkDeviceCreateInfo info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    info.pNext = &features;
    info.queueCreateInfoCount = 1;
    info.pQueueCreateInfos = &queue;
    info.enabledExtensionCount = uint32_t(extensions.size());
    info.ppEnabledExtensionNames = extensions.data();
    PBDSPLAT_VK_TRY(vkCreateDevice(best, &info, nullptr, &dev->device_));
    vkGetDeviceQueue(dev->device_, dev->queue_family_, 0, &dev->queue_);
    return dev;
}

void Device::wait_idle() const {
    if (device_ != VK_NULL_HANDLE) vkDeviceWaitIdle(device_);
}

Device::~Device() {
    if (device_ != VK_NULL_HANDLE) {
        vkDeviceWaitIdle(device_);
        vkDestroyDevice(device_, nullptr);
    }
}

} // namespace pbdsplat::gpu
