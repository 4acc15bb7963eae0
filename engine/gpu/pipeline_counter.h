#pragma once
// What the device did for a span of draws, counted by pipeline-statistics queries: primitives
// that reached clipping and fragment-shader invocations. Counts, unlike timings, do not move with
// the machine's speed or load, so they can hold a pass's work to a figure (tests, the work guard).
#include <cstdint>

#include "gpu/context.h"
#include "gpu/device_handle.h"

namespace pbdsplat::gpu {

struct PipelineCounts {
    uint64_t primitives = 0;  // primitives the clipping stage received (a splat's quad is two)
    uint64_t fragments = 0;   // fragment-shader invocations
    PipelineCounts& operator+=(const PipelineCounts& o) {
        primitives += o.primitives, fragments += o.fragments;
        return *this;
    }
};

class PipelineCounter {
public:
    // Disabled (every call a no-op, read() all zeros) where the device lacks the
    // pipelineStatisticsQuery feature.
    static core::Result<PipelineCounter> create(const Context& ctx, uint32_t max_spans);
    PipelineCounter() = default;

    void reset(VkCommandBuffer cmd);  // outside a render pass, before the frame's spans
    // A span may lie inside one render pass instance or around whole ones, never across an edge.
    void begin(VkCommandBuffer cmd);
    void end(VkCommandBuffer cmd);
    // The spans' sum; call after the frame's fence has signalled.
    core::Result<PipelineCounts> read(VkDevice device) const;

private:
    QueryPool pool_;
    uint32_t capacity_ = 0;
    uint32_t used_ = 0;
    bool open_ = false;
};

} // namespace pbdsplat::gpu
