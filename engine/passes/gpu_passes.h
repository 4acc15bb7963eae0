#pragma once
// The GPU passes of a frame (upload, splat, readback) declared into a frame graph, which
// derives their barriers from the uses in render/splat_renderer.h.
#include <functional>
#include <span>
#include <vector>

#include "graph/frame_graph.h"
#include "render/splat_renderer.h"
#include "splat/gaussian_record.h"

namespace pbdsplat::passes {

// The splats a frame hands to the GPU (the map and sort passes write them).
struct SplatStream {
    std::span<const splat::GaussianRecord> records;
    std::vector<gpu::ByteRange> changed;  // since the previous frame; empty: everything
    std::span<const splat::GaussianShape> shapes;  // anisotropic splats' axes, parallel to records; or none
    std::span<const splat::GaussianSH> sh;         // view-dependent colour, parallel to records; or none
    std::span<const splat::GaussianTexcoord> texcoords;  // textured splats, parallel to records; or none
};
// The surface mesh, with frame.style.mesh_occluders (render/occluder_pass.h; the occluder-mesh
// pass writes it).
struct OccluderInput {
    std::span<const Vec4f> positions;
    std::span<const std::array<uint32_t, 3>> triangles;
    size_t one_sided = 0;  // the leading triangles that close solids (OccluderPass::set_mesh)
};
// What the GPU passes read each frame, kept by its owner and filled before FrameGraph::execute:
// three resources to the graph, one per kind of writer (the camera and style: the events and
// the map; the splats; the occluder mesh), so a pass declares only the part it touches.
struct GpuFrameInput {
    SplatStream splats;
    render::FrameInputs frame;
    OccluderInput occluders;
};
struct GpuInputHandles {
    graph::Handle<render::FrameInputs> frame;
    graph::Handle<SplatStream> splats;
    graph::Handle<OccluderInput> occluders;
};
GpuInputHandles import_gpu_input(graph::FrameGraph& g, GpuFrameInput& input);

// Where a rendered image leaves the frame (a PNG, a test); absent when presenting to a window.
struct ImageSink {};

// The renderer's GPU resources as the graph sees them; refresh() before each execute, since
// the record buffer and the readback buffer change with the frame slot.
struct GpuPassResources {
    graph::GpuBufferRef records, readback;
    graph::GpuBufferRef sorted, sort_control, sort_order;  // with the GPU sort
    graph::GpuImageRef color{VK_NULL_HANDLE, VK_IMAGE_ASPECT_COLOR_BIT};
    graph::GpuImageRef depth{VK_NULL_HANDLE, VK_IMAGE_ASPECT_DEPTH_BIT};
    // With normalised blending: its sums of the seen side and of the inside.
    graph::GpuImageRef accumulation{VK_NULL_HANDLE, VK_IMAGE_ASPECT_COLOR_BIT};
    graph::GpuImageRef accumulation_inside{VK_NULL_HANDLE, VK_IMAGE_ASPECT_COLOR_BIT};
    graph::GpuImageRef occluders{VK_NULL_HANDLE, VK_IMAGE_ASPECT_COLOR_BIT};  // with mesh occluders
    void refresh(const render::SplatRenderer& r);
};

graph::GpuUse to_graph(const render::Use& u);

// The images a windowed frame shows, as the graph has them after drawing.
struct PresentSources {
    graph::Handle<graph::GpuImageRef> splats;  // the splat pass's colour target
    graph::Handle<graph::GpuImageRef> mesh;    // the lit mesh raster's, when the view asks for it
    uint32_t width = 0, height = 0;            // of both targets
    std::function<uint32_t()> slot;            // the frame slot being recorded
};

// Where a windowed frame goes (the demo's swapchain): declares the passes that take the drawn
// images to the screen, and the semaphores this frame's submit waits on and signals.
class Presenter {
public:
    virtual ~Presenter() = default;
    virtual void add_passes(graph::FrameGraph& g, const PresentSources& sources) = 0;
    virtual const VkSemaphoreSubmitInfo* wait_semaphore() const = 0;
    virtual const VkSemaphoreSubmitInfo* signal_semaphore() const = 0;
};

// Declares "upload", "gpu sort" (when `gpu_sort`: the frames are drawn with SplatOrder::gpu),
// "splat", "occluders" (when the renderer has mesh occluders), "splat accumulate" and "splat
// resolve" (when the renderer has normalised blending), or else "splat over occluders" (the
// paper's disc, when it has mesh occluders)
// and "readback". The readback pass needs `sink`; without one it is culled. `input` is
// the version of the frame input the passes read (after the mapping); `upload_status` what the
// upload and occluder passes leave there (the frame's owner reports a failure; import it
// persistent).
// Returns the colour target as the splat pass leaves it.
graph::Handle<graph::GpuImageRef> add_gpu_passes(graph::FrameGraph& g, render::SplatRenderer& renderer,
                                                 GpuPassResources& resources, const GpuInputHandles& input,
                                                 graph::Handle<core::Status> upload_status, graph::Handle<ImageSink> sink, bool gpu_sort = false,
                                                 uint32_t tag = 0);

// The byte ranges of `after` that differ from `before` (all of it when the counts differ), so
// only what changed is uploaded; a single empty range when nothing did.
void changed_ranges(std::span<const splat::GaussianRecord> before, std::span<const splat::GaussianRecord> after,
                    std::vector<gpu::ByteRange>& out);

} // namespace pbdsplat::passes
