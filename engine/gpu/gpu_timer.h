#pragma once
// GPU timestamps per frame: mark() between passes, read the intervals once the frame is done.
#include <string>
#include <vector>

#include "gpu/context.h"
#include "gpu/device_handle.h"

namespace pbdsplat::gpu {

class GpuTimer {
public:
    static core::Result<GpuTimer> create(const Context& ctx, uint32_t max_marks);
    GpuTimer() = default;
    bool enabled() const { return static_cast<bool>(pool_); }

    void begin(VkCommandBuffer cmd);  // resets the marks
    // `stage`: the stage whose completion by all earlier commands the mark waits for.
    void mark(VkCommandBuffer cmd, const char* label, VkPipelineStageFlags2 stage);
    // Milliseconds between consecutive marks ({label of the later mark, ms}); call after the
    // frame's fence has signalled.
    core::Result<std::vector<std::pair<std::string, double>>> read(VkDevice device) const;

private:
    QueryPool pool_;
    uint32_t capacity_ = 0;
    uint32_t used_ = 0;
    float period_ns_ = 1.0f;
    std::vector<std::string> labels_;
};

} // namespace pbdsplat::gpu
