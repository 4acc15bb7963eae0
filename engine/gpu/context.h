#pragma once
// Everything a GPU pass needs to make resources: instance, device and memory, made together.
#include <memory>

#include "gpu/device.h"
#include "gpu/memory.h"

namespace pbdsplat::gpu {

struct ContextOptions {
    InstanceOptions instance;
    DeviceOptions device;
};

class Context {
public:
    static core::Result<std::unique_ptr<Context>> create(const ContextOptions& options);
    ~Context();

    const Instance& instance() const { return *instance_; }
    Instance& instance() { return *instance_; }
    const Device& device() const { return *device_; }
    VkDevice vk() const { return device_->handle(); }
    const DeviceCaps& caps() const { return device_->caps(); }
    MemoryAllocator& memory() { return *memory_; }

    // Validation messages so far (0 when validation is off).
    size_t validation_messages() const { return instance_->validation_log().count(); }

private:
    Context() = default;
    std::unique_ptr<Instance> instance_;
    std::unique_ptr<Device> device_;
    std::unique_ptr<MemoryAllocator> memory_;
};

} // namespace pbdsplat::gpu
