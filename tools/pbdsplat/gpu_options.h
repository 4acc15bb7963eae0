#pragma once
// Opening the Vulkan context with the options every GPU command shares (options.h: gpu_options).
#include <memory>

#include "gpu/context.h"
#include "pbdsplat/options.h"

namespace pbdsplat::cli {

core::Result<std::unique_ptr<gpu::Context>> open_context(const Options& options);

// Fails when validation is on and the layer reported anything.
core::Status check_validation(const gpu::Context& ctx);

} // namespace pbdsplat::cli
