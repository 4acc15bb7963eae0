#pragma once
// The Vulkan instance, with the Khronos validation layer when asked for. Every message the
// layer sends is counted (tests fail on any) and kept for the report.
#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "gpu/vk.h"

namespace pbdsplat::gpu {

struct InstanceOptions {
    bool validation = false;      // enable VK_LAYER_KHRONOS_validation
    bool best_practices = false;  // also its best-practices checks
    bool surface = false;         // request the window-system extensions (windowed demo)
    std::vector<std::string> extra_extensions;
};

// Collects validation messages; thread-safe, since drivers may call back from any thread.
class ValidationLog {
public:
    void add(std::string message);
    size_t count() const { return count_.load(); }
    std::vector<std::string> messages() const;
    void clear();

private:
    std::atomic<size_t> count_{0};
    mutable std::mutex mutex_;
    std::vector<std::string> messages_;  // the first few, verbatim
};

class Instance {
public:
    static core::Result<std::unique_ptr<Instance>> create(const InstanceOptions& options);
    ~Instance();
    Instance(const Instance&) = delete;
    Instance& operator=(const Instance&) = delete;

    VkInstance handle() const { return instance_; }
    bool validation_enabled() const { return messenger_ != VK_NULL_HANDLE; }
    const ValidationLog& validation_log() const { return *log_; }
    ValidationLog& validation_log() { return *log_; }
    // The log outlives the instance for whoever holds this: messages sent while the device and
    // the instance are destroyed (leaked objects) can be read after the teardown.
    std::shared_ptr<const ValidationLog> shared_validation_log() const { return log_; }

private:
    Instance() = default;
    VkInstance instance_ = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
    std::shared_ptr<ValidationLog> log_ = std::make_shared<ValidationLog>();
};

} // namespace pbdsplat::gpu
