#pragma once
// Renders Gaussian records into an offscreen image: upload, splat, readback, with the frames in
// flight, the staging ring and the GPU timestamps that go with them.
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/image.h"
#include "gpu/frame_ring.h"
#include "gpu/gpu_timer.h"
#include "gpu/stream_buffer.h"
#include "render/frame_inputs.h"
#include "render/offscreen_target.h"
#include "render/splat_pass.h"
#include "splat/gaussian_record.h"

namespace pbdsplat::render {

struct RendererOptions {
    uint32_t width = 1280;
    uint32_t height = 720;
    uint32_t max_splats = 1u << 20;
    uint32_t frames_in_flight = 2;
    std::optional<gpu::UploadPath> upload_path;  // default: direct on unified memory, else staged
    bool readback = true;                        // copy every frame back (tests, PNG output)
};

// GPU milliseconds of the last finished frame, from timestamps (0 when the device has none).
struct GpuTimings {
    double upload_cpu_ms = 0.0;  // CPU: writing the records (in place, or into the staging ring)
    double upload_ms = 0.0;      // GPU: the staging copy (about 0 on the direct path)
    double draw_ms = 0.0;
    double readback_ms = 0.0;
};

class OffscreenRenderer {
public:
    static core::Result<std::unique_ptr<OffscreenRenderer>> create(gpu::Context& ctx, const RendererOptions& options);
    ~OffscreenRenderer();

    // Records and submits one frame. `changed` lists the byte ranges of `records` that differ
    // from the previous frame; empty means all of them.
    core::Status render(std::span<const splat::GaussianRecord> records, const FrameInputs& inputs,
                        std::span<const gpu::ByteRange> changed = {});
    // Waits for the GPU and returns the last frame's image (needs readback on).
    core::Result<core::ImageRgba8> finish();
    // Timings of the newest finished frame (GPU figures are 0 without timestamp support).
    GpuTimings timings() const { return timings_; }
    gpu::UploadPath upload_path() const { return records_.path(); }
    uint32_t width() const { return target_.width(); }
    uint32_t height() const { return target_.height(); }

private:
    OffscreenRenderer() = default;
    core::Status collect_timings(uint32_t slot);

    gpu::Context* ctx_ = nullptr;
    RendererOptions options_;
    gpu::FrameRing frames_;
    gpu::UploadRing ring_;
    gpu::StreamBuffer records_;
    OffscreenTarget target_;
    SplatPass splat_;
    gpu::DescriptorPool descriptor_pool_;
    std::vector<gpu::Buffer> uniforms_;         // one per frame in flight
    std::vector<VkDescriptorSet> sets_;         // one per frame in flight
    std::vector<gpu::GpuTimer> timers_;         // one per frame in flight
    std::vector<bool> slot_pending_;            // slot has a submitted frame whose timings are unread
    uint32_t last_slot_ = 0;
    bool any_frame_ = false;
    GpuTimings timings_;
    std::vector<double> upload_cpu_ms_;  // per slot, measured while recording
};

} // namespace pbdsplat::render
