#pragma once
#include <optional>
#include <string>

#include "gpu/stream_buffer.h"
#include "pbdsplat/options.h"

namespace pbdsplat::cli {

// --upload auto|staged|direct; auto (nullopt) lets the renderer choose per device.
inline Option upload_option() {
    return choice("upload", {"auto", "staged", "direct"}, "auto",
                  "how records reach the GPU: auto chooses per device, staged copies from a host-visible ring,\n"
                  "direct writes device-local memory the host can see");
}

inline std::optional<gpu::UploadPath> upload_path(const Options& options) {
    const std::string& s = options.text("upload");
    if (s == "staged") return gpu::UploadPath::staged;
    if (s == "direct") return gpu::UploadPath::direct;
    return std::nullopt;
}

} // namespace pbdsplat::cli
