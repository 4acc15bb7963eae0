#pragma once
#include <optional>
#include <string>

#include "core/result.h"
#include "gpu/stream_buffer.h"

namespace pbdsplat::cli {

// --upload auto|staged|direct; auto (nullopt) lets the renderer choose per device.
inline core::Result<std::optional<gpu::UploadPath>> parse_upload_path(const std::string& s) {
    if (s == "auto") return std::optional<gpu::UploadPath>{};
    if (s == "staged") return std::optional<gpu::UploadPath>{gpu::UploadPath::staged};
    if (s == "direct") return std::optional<gpu::UploadPath>{gpu::UploadPath::direct};
    return core::make_error("--upload must be auto, staged or direct, got '" + s + "'");
}

} // namespace pbdsplat::cli
