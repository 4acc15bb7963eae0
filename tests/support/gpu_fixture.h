#pragma once
// Every GPU test opens its device through here: the Khronos validation layer (with its
// best-practices and synchronization checks) is always on, and a test fails if it reports
// anything, up to and including the teardown. No device is a failure, not a skip: CI must have
// Lavapipe.
#include <doctest/doctest.h>

#include <memory>

#include "gpu/context.h"

namespace pbdsplat::test {

// The test's device. Declared first in a test, it is destroyed last: its destructor tears the
// device and the instance down and then fails the test on any validation message, so errors in
// destructors and objects leaked at vkDestroyDevice count too.
class ValidatedContext {
public:
    explicit ValidatedContext(std::unique_ptr<gpu::Context> ctx)
        : ctx_(std::move(ctx)), log_(ctx_->instance().shared_validation_log()) {}
    ValidatedContext(const ValidatedContext&) = delete;
    ValidatedContext& operator=(const ValidatedContext&) = delete;
    ~ValidatedContext() {
        ctx_.reset();
        for (const auto& m : log_->messages()) INFO(m);
        CHECK_MESSAGE(log_->count() == 0, "validation messages by the end of the teardown: " << log_->count());
    }

    gpu::Context* get() const { return ctx_.get(); }
    gpu::Context* operator->() const { return ctx_.get(); }
    gpu::Context& operator*() const { return *ctx_; }

private:
    std::unique_ptr<gpu::Context> ctx_;
    std::shared_ptr<const gpu::ValidationLog> log_;
};

inline ValidatedContext open_validated_context() {
    gpu::ContextOptions o;
    o.instance.validation = true;
    o.instance.best_practices = true;
    auto ctx = gpu::Context::create(o);
    if (!ctx.ok()) FAIL("no usable Vulkan device with validation: " << ctx.error().to_string());
    return ValidatedContext(std::move(ctx).value());
}

// Checks the layer stayed silent so far; call at the end of each test (the teardown is checked
// when the context goes).
inline void require_no_validation_messages(const gpu::Context& ctx) {
    const auto messages = ctx.instance().validation_log().messages();
    for (const auto& m : messages) INFO(m);
    CHECK_MESSAGE(ctx.validation_messages() == 0, "validation messages: " << ctx.validation_messages());
}

} // namespace pbdsplat::test
