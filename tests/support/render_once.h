#pragma once
// One offscreen frame of the given records through a fresh renderer: what the image tests draw;
// with `occluders`, their mesh hides what lies behind it (frame.style.mesh_occluders).
#include <algorithm>
#include <optional>
#include <span>
#include <vector>

#include <doctest/doctest.h>

#include "core/image.h"
#include "passes/offscreen_renderer.h"
#include "support/splat_reference.h"
#include "support/why.h"

namespace pbdsplat::test {

inline core::ImageRgba8 render_once(gpu::Context& ctx, const std::vector<splat::GaussianRecord>& records,
                                    const render::FrameInputs& frame, uint32_t w, uint32_t h,
                                    std::optional<render::SplatPath> path = render::SplatPath::geometry,
                                    render::SplatShading shading = render::SplatShading::fragment,
                                    render::SplatCarrier carrier = render::SplatCarrier::quad,
                                    std::span<const splat::GaussianShape> shapes = {}, const OccluderMesh* occluders = nullptr) {
    render::RendererOptions o;
    o.path = path;
    o.shading = shading;
    o.carrier = carrier;
    o.anisotropic = !shapes.empty();  // one shape per record: drawn with their axes
    o.normalised = frame.style.blend == render::Blend::normalised;
    o.width = w;
    o.height = h;
    o.max_splats = std::max<uint32_t>(1, uint32_t(records.size()));
    o.frames_in_flight = 1;
    o.occluders = occluders != nullptr;
    auto r = passes::OffscreenRenderer::create(ctx, o);
    REQUIRE_MESSAGE(r.ok(), test::why(r));
    if (occluders) r.value()->set_occluders(occluders->x, occluders->triangles);
    const auto status = r.value()->render(records, frame, {}, shapes);
    REQUIRE_MESSAGE(status.ok(), test::why(status));
    auto img = r.value()->finish();
    REQUIRE_MESSAGE(img.ok(), test::why(img));
    return std::move(img).value();
}

} // namespace pbdsplat::test
