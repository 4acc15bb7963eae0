#include "gpu/instance.h"

#include <cstdio>
#include <cstring>

namespace pbdsplat::gpu {

void ValidationLog::add(std::string message) {
    count_.fetch_add(1);
    std::lock_guard lock(mutex_);
    if (messages_.size() < 64) messages_.push_back(std::move(message));
}

std::vector<std::string> ValidationLog::messages() const {
    std::lock_guard lock(mutex_);
    return messages_;
}

void ValidationLog::clear() {
    std::lock_guard lock(mutex_);
    messages_.clear();
    count_.store(0);
}

namespace {

VKAPI_ATTR VkBool32 VKAPI_CALL on_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                          VkDebugUtilsMessageTypeFlagsEXT, const VkDebugUtilsMessengerCallbackDataEXT* data,
                                          void* user) {
    // Best practices flags VK_EXT_debug_utils itself as "for debugging only": that is exactly
    // what this messenger is, so the one message about our own use of it is not counted.
    constexpr int32_t k_debug_utils_special_use = int32_t(0x822806fa);
    if (data && data->messageIdNumber == k_debug_utils_special_use) return VK_FALSE;
    const char* level = (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) ? "error" : "warning";
    std::string text = std::string("[validation ") + level + "] " + (data && data->pMessage ? data->pMessage : "");
    std::fprintf(stderr, "%s\n", text.c_str());
    static_cast<ValidationLog*>(user)->add(std::move(text));
    return VK_FALSE;  // never abort the call: the count is what fails a test
}

bool has_layer(const char* name) {
    uint32_t n = 0;
    vkEnumerateInstanceLayerProperties(&n, nullptr);
    std::vector<VkLayerProperties> layers(n);
    vkEnumerateInstanceLayerProperties(&n, layers.data());
    for (const auto& l : layers)
        if (std::strcmp(l.layerName, name) == 0) return true;
    return false;
}

bool has_extension(const std::vector<VkExtensionProperties>& all, const char* name) {
    for (const auto& e : all)
        if (std::strcmp(e.extensionName, name) == 0) return true;
    return false;
}

// The layers and instance extensions the options ask for, each checked to be present.
struct Wanted {
    std::vector<const char*> layers, extensions;
};
core::Result<Wanted> wanted_for(const InstanceOptions& options) {
    constexpr const char* k_layer = "VK_LAYER_KHRONOS_validation";
    uint32_t n = 0;
    vkEnumerateInstanceExtensionProperties(nullptr, &n, nullptr);
    std::vector<VkExtensionProperties> available(n);
    vkEnumerateInstanceExtensionProperties(nullptr, &n, available.data());
    Wanted w;
    if (options.validation) {
        if (!has_layer(k_layer))
            return core::make_error("validation was requested but VK_LAYER_KHRONOS_validation is not installed "
                                    "(apt-get install vulkan-validationlayers, or run tools/setup)");
        w.layers.push_back(k_layer);
        w.extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    }
    if (options.surface) {
        for (const char* e : {"VK_KHR_surface", "VK_KHR_xlib_surface", "VK_KHR_xcb_surface", "VK_KHR_wayland_surface"})
            if (has_extension(available, e)) w.extensions.push_back(e);
    }
    for (const auto& e : options.extra_extensions) {
        if (!has_extension(available, e.c_str())) return core::make_error("the Vulkan instance lacks the extension " + e);
        w.extensions.push_back(e.c_str());
    }
    return w;
}

} // namespace

core::Result<std::unique_ptr<Instance>> Instance::create(const InstanceOptions& options) {
    uint32_t api = 0;
    if (vkEnumerateInstanceVersion(&api) != VK_SUCCESS || api < VK_API_VERSION_1_3)
        return core::make_error("the Vulkan loader is older than 1.3; install Debian's libvulkan1 (tools/setup)");
    auto wanted = wanted_for(options);
    if (!wanted.ok()) return wanted.error();
    const std::vector<const char*>& layers = wanted->layers;
    const std::vector<const char*>& extensions = wanted->extensions;

    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "pbdsplat";
    app.applicationVersion = VK_MAKE_VERSION(0, 1, 0);
    app.pEngineName = "pbdsplat";
    app.apiVersion = VK_API_VERSION_1_3;

    VkDebugUtilsMessengerCreateInfoEXT messenger_info{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    messenger_info.messageSeverity =
        VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    messenger_info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                                 VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                                 VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    messenger_info.pfnUserCallback = on_message;

    auto inst = std::unique_ptr<Instance>(new Instance());
    messenger_info.pUserData = inst->log_.get();

    const VkValidationFeatureEnableEXT enables[] = {VK_VALIDATION_FEATURE_ENABLE_BEST_PRACTICES_EXT,
                                                    VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
    VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
    features.enabledValidationFeatureCount = options.best_practices ? 2u : 1u;
    features.pEnabledValidationFeatures = options.best_practices ? enables : enables + 1;
    features.pNext = &messenger_info;  // also catches messages from vkCreateInstance itself

    VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    info.pApplicationInfo = &app;
    info.enabledLayerCount = uint32_t(layers.size());
    info.ppEnabledLayerNames = layers.data();
    info.enabledExtensionCount = uint32_t(extensions.size());
    info.ppEnabledExtensionNames = extensions.data();
    if (options.validation) info.pNext = &features;
    PBDSPLAT_VK_TRY(vkCreateInstance(&info, nullptr, &inst->instance_));

    if (options.validation) {
        auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(inst->instance_, "vkCreateDebugUtilsMessengerEXT"));
        if (!create) return core::make_error("vkCreateDebugUtilsMessengerEXT is missing though validation is on");
        PBDSPLAT_VK_TRY(create(inst->instance_, &messenger_info, nullptr, &inst->messenger_));
    }
    return inst;
}

Instance::~Instance() {
    if (messenger_ != VK_NULL_HANDLE) {
        auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
        if (destroy) destroy(instance_, messenger_, nullptr);
    }
    if (instance_ != VK_NULL_HANDLE) vkDestroyInstance(instance_, nullptr);
}

} // namespace pbdsplat::gpu
