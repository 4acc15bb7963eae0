#pragma once
// Options every GPU command shares (--validation, --device), and opening the context with them.
#include <memory>
#include <set>
#include <string>

#include "gpu/context.h"
#include "pbdsplat/args.h"

namespace pbdsplat::cli {

inline const std::set<std::string> k_gpu_flags = {"validation"};
inline const std::set<std::string> k_gpu_options = {"device"};
constexpr const char* k_gpu_help =
    "  --validation        enable the Khronos validation layer; any message makes the command fail\n"
    "  --device NAME       pick the Vulkan device whose name contains NAME (also $PBDSPLAT_DEVICE)\n";

core::Result<std::unique_ptr<gpu::Context>> open_context(const Args& args);

// Fails when validation is on and the layer reported anything.
core::Status check_validation(const gpu::Context& ctx);

} // namespace pbdsplat::cli
