#pragma once
// Opening the Vulkan context with the options every GPU command shares (options.h: gpu_options).
#include <memory>

#include "gpu/context.h"
#include "pbdsplat/options.h"

namespace pbdsplat::cli {

core::Result<std::unique_ptr<gpu::Context>> open_context(const Options& options);

// Fails when validation is on and the layer reported anything so far.
core::Status check_validation(const gpu::Context& ctx);
// Destroys the context, then fails if the layer reported anything in its whole life, teardown
// included: an object left alive past the device is reported only as the device goes.
core::Status close_and_check_validation(std::unique_ptr<gpu::Context> ctx);

} // namespace pbdsplat::cli
