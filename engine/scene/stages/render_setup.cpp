#include "scene/stages/render_setup.h"

#include <algorithm>

#include "render/gpu_sort.h"

namespace pbdsplat::scene {

SortChoice choose_sort(const Scene& scene, std::optional<render::SplatOrder> override_, const gpu::DeviceCaps* caps) {
    SortChoice c;
    c.when_sorted = override_.value_or(scene.render.sort_on.value_or(caps ? render::preferred_sort(*caps) : render::SplatOrder::cpu));
    // The GPU sort reorders records only; anisotropic shapes travel with the CPU's.
    if (!caps || scene.render.deformed_shapes()) c.when_sorted = render::SplatOrder::cpu;
    if (scene.render.sort && scene.render.frame.style.blend == render::Blend::over) c.order = c.when_sorted;
    return c;
}

render::RendererOptions renderer_options(const Scene& scene, const SortChoice& sort, const RendererNeeds& needs, size_t* max_samples) {
    render::RendererOptions ro;
    ro.shading = scene.render.shading;
    ro.carrier = scene.render.carrier;
    ro.anisotropic = scene.render.deformed_shapes();
    // Interactive runs may switch the sort on later: have it ready.
    ro.gpu_sort = sort.order == render::SplatOrder::gpu || (needs.interactive && sort.when_sorted == render::SplatOrder::gpu);
    ro.normalised = scene.render.frame.style.blend == render::Blend::normalised;
    ro.occluders = render::occluded_style(scene.render.frame.style);
    ro.width = scene.render.width;
    ro.height = scene.render.height;
    // A cut duplicates vertices along its path: leave room for them. Tearing keeps opening new
    // boundary: more room than for scripted cuts; interactive runs, cut again and again, most.
    bool tears = false;
    for (const Event& e : scene.events) tears = tears || std::holds_alternative<TearEvent>(e.data);
    const size_t room = needs.interactive || tears ? 4 : scene.has_topology_events() ? 2 : 1;
    // Density control adds samples where the surface grows: room for three times the area.
    const size_t grow = needs.density ? 3 : 1;
    ro.max_splats = uint32_t(std::max<size_t>(1, room * grow * needs.splats));
    if (max_samples) *max_samples = grow * needs.splats;
    ro.textures = needs.textures;
    ro.path = scene.render.splat_path;
    ro.environment_map = scene.render.environment_map;
    ro.sky_sun = scene.render.frame.lighting.direction;
    return ro;
}

} // namespace pbdsplat::scene
