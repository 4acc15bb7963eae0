#include "gpu/context.h"

namespace pbdsplat::gpu {

core::Result<std::unique_ptr<Context>> Context::create(const ContextOptions& options) {
    auto ctx = std::unique_ptr<Context>(new Context());
    auto instance = Instance::create(options.instance);
    if (!instance.ok()) return instance.error();
    ctx->instance_ = std::move(instance).value();
    DeviceOptions device_options = options.device;
    device_options.swapchain = device_options.swapchain || options.instance.surface;
    auto device = Device::create(*ctx->instance_, device_options);
    if (!device.ok()) return device.error();
    ctx->device_ = std::move(device).value();
    ctx->memory_ = std::make_unique<MemoryAllocator>(ctx->device_->handle(), ctx->device_->memory_properties(),
                                                     ctx->device_->limits().bufferImageGranularity);
    return ctx;
}

Context::~Context() {
    if (device_) device_->wait_idle();
    memory_.reset();  // memory goes before the device that owns it
    device_.reset();
    instance_.reset();
}

} // namespace pbdsplat::gpu
