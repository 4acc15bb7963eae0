#include "scene/coverage.h"

#include "gpu/frame_ring.h"
#include "graph/frame_graph.h"
#include "render/mesh_raster.h"
#include "scene/gpu_passes.h"
#include "scene/offscreen_renderer.h"

namespace pbdsplat::scene {
namespace {

// The mesh mask through a small frame graph: raster, then readback; barriers derived.
core::Result<core::ImageRgba8> mesh_mask(gpu::Context& ctx, std::span<const Vec4f> x,
                                         std::span<const std::array<uint32_t, 3>> triangles,
                                         const render::FrameInputs& frame, uint32_t width, uint32_t height) {
    render::MeshRasterOptions mo;
    mo.width = width;
    mo.height = height;
    mo.max_vertices = x.size();
    mo.max_triangles = triangles.size();
    auto raster = render::MeshRaster::create(ctx, mo);
    if (!raster.ok()) return raster.error();
    render::MeshRaster& m = *raster.value();
    PBDSPLAT_TRY(m.set_mesh(x, triangles));
    graph::GpuImageRef color{m.color_image(), VK_IMAGE_ASPECT_COLOR_BIT}, depth{m.depth_image(), VK_IMAGE_ASPECT_DEPTH_BIT};
    graph::GpuBufferRef readback{m.readback_buffer()};
    ImageSink sink;
    graph::FrameGraph g;
    auto hc = g.import("mesh colour", &color);
    auto hd = g.import("mesh depth", &depth);
    auto hr = g.import("mesh readback", &readback);
    auto hs = g.import("image", &sink);
    g.add_pass("mesh raster", graph::PassKind::gpu, [&](graph::PassBuilder& b) {
        hc = b.write(hc, to_graph(render::uses::color_attachment));
        b.write(hd, to_graph(render::uses::depth_attachment));
        return [&m, &frame](const graph::PassResources&, graph::ExecuteContext& c) { m.draw(c.cmd, frame); };
    });
    g.add_pass("mesh readback", graph::PassKind::gpu, [&](graph::PassBuilder& b) {
        b.read(hc, to_graph(render::uses::color_copy_source));
        b.write(hr, to_graph(render::uses::readback_write));
        b.write(hs);
        b.side_effect();
        return [&m](const graph::PassResources&, graph::ExecuteContext& c) { m.readback(c.cmd); };
    });
    PBDSPLAT_TRY(g.compile());
    auto ring = gpu::FrameRing::create(ctx, 1);
    if (!ring.ok()) return ring.error();
    auto cmd = ring->begin();
    if (!cmd.ok()) return cmd.error();
    graph::ExecuteContext ec{cmd.value(), 0};
    g.execute(ec);
    PBDSPLAT_TRY(ring->submit());
    PBDSPLAT_TRY(ring->wait_all());
    return m.read();
}

} // namespace

core::Result<Coverage> measure_coverage(gpu::Context& ctx, std::span<const Vec4f> x,
                                        std::span<const std::array<uint32_t, 3>> triangles,
                                        std::span<const splat::GaussianRecord> records, render::FrameInputs frame,
                                        uint32_t width, uint32_t height) {
    Coverage c;
    auto mesh = mesh_mask(ctx, x, triangles, frame, width, height);
    if (!mesh.ok()) return mesh.error();
    c.mesh = std::move(mesh).value();

    render::RendererOptions ro;
    ro.width = width;
    ro.height = height;
    ro.max_splats = uint32_t(std::max<size_t>(1, records.size()));
    ro.frames_in_flight = 1;
    auto splats = OffscreenRenderer::create(ctx, ro);
    if (!splats.ok()) return splats.error();
    frame.background = Vec4f::Zero();  // the accumulated alpha is then the splats' coverage
    PBDSPLAT_TRY(splats.value()->render(records, frame));
    auto image = splats.value()->finish();
    if (!image.ok()) return image.error();
    c.splats = std::move(image).value();

    size_t holes = 0, both = 0, either = 0;
    for (size_t i = 0; i < size_t(width) * height; ++i) {
        const bool in_mesh = c.mesh.pixels[i * 4 + 3] >= 128;
        const bool in_splats = c.splats.pixels[i * 4 + 3] >= 128;
        c.mesh_pixels += in_mesh ? 1 : 0;
        holes += (in_mesh && !in_splats) ? 1 : 0;
        both += (in_mesh && in_splats) ? 1 : 0;
        either += (in_mesh || in_splats) ? 1 : 0;
    }
    if (c.mesh_pixels == 0) return core::make_error("the mesh is not in view: no coverage to measure");
    c.hole_ratio = double(holes) / double(c.mesh_pixels);
    c.silhouette_iou = double(both) / double(either);
    return c;
}

} // namespace pbdsplat::scene
