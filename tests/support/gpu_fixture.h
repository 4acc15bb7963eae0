#pragma once
// Every GPU test opens its device through here: the Khronos validation layer (with its
// best-practices and synchronization checks) is always on, and a test fails if it reports
// anything. No device is a failure, not a skip: CI must have Lavapipe.
#include <doctest/doctest.h>

#include <memory>

#include "gpu/context.h"

namespace pbdsplat::test {

inline std::unique_ptr<gpu::Context> open_validated_context() {
    gpu::ContextOptions o;
    o.instance.validation = true;
    o.instance.best_practices = true;
    auto ctx = gpu::Context::create(o);
    if (!ctx.ok()) FAIL("no usable Vulkan device with validation: " << ctx.error().to_string());
    return std::move(ctx).value();
}

// Checks the layer stayed silent; call at the end of each test.
inline void require_no_validation_messages(const gpu::Context& ctx) {
    const auto messages = ctx.instance().validation_log().messages();
    for (const auto& m : messages) INFO(m);
    CHECK_MESSAGE(ctx.validation_messages() == 0, "validation messages: " << ctx.validation_messages());
}

} // namespace pbdsplat::test
