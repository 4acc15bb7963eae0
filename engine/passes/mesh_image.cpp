#include "passes/mesh_image.h"

#include "gpu/frame_ring.h"
#include "gpu/gpu_timer.h"
#include "graph/frame_graph.h"
#include "passes/gpu_passes.h"

namespace pbdsplat::passes {

core::Result<MeshImage> render_mesh_image(gpu::Context& ctx, render::MeshRaster& m, const render::FrameInputs& frame,
                                          render::MeshView view, const Vec3f& albedo) {
    graph::GpuImageRef color{m.color_image(), VK_IMAGE_ASPECT_COLOR_BIT}, depth{m.depth_image(), VK_IMAGE_ASPECT_DEPTH_BIT};
    graph::GpuBufferRef readback{m.readback_buffer()};
    ImageSink sink;
    auto timer = gpu::GpuTimer::create(ctx, 4);
    if (!timer.ok()) return timer.error();
    graph::FrameGraph g;
    auto hc = g.import("mesh colour", &color);
    auto hd = g.import("mesh depth", &depth);
    auto hr = g.import("mesh readback", &readback);
    auto hs = g.import("image", &sink);
    gpu::GpuTimer& t = timer.value();
    g.add_pass("mesh raster", graph::PassKind::gpu, [&](graph::PassBuilder& b) {
        hc = b.write(hc, to_graph(render::uses::color_attachment));
        b.write(hd, to_graph(render::uses::depth_attachment));
        return [&](const graph::PassResources&, graph::ExecuteContext& c) {
            t.mark(c.cmd, "start", VK_PIPELINE_STAGE_2_TOP_OF_PIPE_BIT);
            m.draw(c.cmd, frame, view, albedo);
            t.mark(c.cmd, "raster", VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT);
        };
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
    t.begin(cmd.value());
    graph::ExecuteContext ec{cmd.value(), 0};
    g.execute(ec);
    PBDSPLAT_TRY(ring->submit());
    PBDSPLAT_TRY(ring->wait_all());
    MeshImage out;
    out.image = m.read();
    auto marks = t.read(ctx.vk());
    if (!marks.ok()) return marks.error();
    for (const auto& [label, ms] : marks.value())
        if (label == "raster") out.gpu_ms = ms;
    return out;
}

} // namespace pbdsplat::passes
