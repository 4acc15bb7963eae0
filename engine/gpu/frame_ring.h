#pragma once
// Frames in flight: one command buffer, fence and retire list per slot. An object that a
// recorded frame still uses is handed to retire() and destroyed only once that frame's fence
// has signalled, so nothing is freed under the GPU's feet.
#include <cstdint>
#include <functional>
#include <vector>

#include "gpu/context.h"
#include "gpu/device_handle.h"

namespace pbdsplat::gpu {

class FrameRing {
public:
    static core::Result<FrameRing> create(Context& ctx, uint32_t frames_in_flight);
    FrameRing() = default;
    FrameRing(FrameRing&&) noexcept = default;
    FrameRing& operator=(FrameRing&&) noexcept = default;
    ~FrameRing();

    // Waits for the slot's previous use, runs its retirements and starts recording.
    core::Result<VkCommandBuffer> begin();
    // Ends recording and submits; the fence of this slot signals when the GPU is done.
    core::Status submit(const VkSemaphoreSubmitInfo* wait = nullptr, const VkSemaphoreSubmitInfo* signal = nullptr);
    // Blocks until every submitted frame has finished, and retires everything.
    core::Status wait_all();

    // Keeps `destroy` until the frame being recorded now has finished on the GPU.
    void retire(std::function<void()> destroy);

    uint32_t slot() const { return slot_; }
    uint32_t frames_in_flight() const { return uint32_t(slots_.size()); }
    uint64_t serial() const { return serial_; }               // of the frame being recorded
    uint64_t completed_serial() const { return completed_; }  // newest frame known finished
    VkCommandBuffer cmd() const { return slots_[slot_].cmd; }

private:
    struct Slot {
        CommandPool pool;
        VkCommandBuffer cmd = VK_NULL_HANDLE;
        Fence fence;
        uint64_t serial = 0;  // 0: never submitted
        std::vector<std::function<void()>> retired;
    };
    core::Status wait_slot(Slot& s);

    Context* ctx_ = nullptr;
    std::vector<Slot> slots_;
    uint32_t slot_ = 0;
    uint64_t serial_ = 0;
    uint64_t completed_ = 0;
    bool recording_ = false;
};

} // namespace pbdsplat::gpu
