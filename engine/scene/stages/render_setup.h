#pragma once
// What a scene asks of the renderer, decided once when its runtime is built: where the far-to-
// near sort runs, and the renderer's options (capacity for what cuts, tears and the density
// control may add).
#include <cstddef>
#include <optional>

#include "gpu/device.h"
#include "render/frame_inputs.h"
#include "render/splat_renderer.h"
#include "scene/scene.h"

namespace pbdsplat::scene {

struct SortChoice {
    render::SplatOrder order = render::SplatOrder::unsorted;  // what the scene draws with now
    render::SplatOrder when_sorted = render::SplatOrder::cpu;  // what turning the sort on picks
};

// The override, the scene's choice, or what suits the device (`caps`; null: no device, and the
// CPU is the only place to sort).
SortChoice choose_sort(const Scene& scene, std::optional<render::SplatOrder> override_, const gpu::DeviceCaps* caps);

struct RendererNeeds {
    size_t splats = 0;        // particles and boundary particles at the start
    bool interactive = false;  // may be cut again and again, sorted later
    bool density = false;      // the density control adds samples where the surface grows
    uint32_t textures = 0;     // the textures the samples say lie on them (paint.h), if any
};
// `max_samples`: receives what the density control may fill (the capacity less the cuts' room).
render::RendererOptions renderer_options(const Scene& scene, const SortChoice& sort, const RendererNeeds& needs,
                                         size_t* max_samples = nullptr);

} // namespace pbdsplat::scene
