#pragma once
// Mesh occluders (render.visibility = "mesh"; normalised blending, or the paper's disc under
// "over"): the surface mesh the splats stand for is rasterised once, both sides, into the splat
// target's depth (pushed back along the view rays) and, as its distance along the view axis,
// into a float image that the splats' fragment stage reads. It then keeps only the fragments
// lying on the surface the mesh shows at each pixel (within a tolerance), so a splat ends at
// every occluding contour and crease where the mesh does, instead of painting the surface behind
// it over with its own colour; past the body's outline (no surface) a splat keeps one pixel of
// its rim (shaders/shared/splat_fragment.glsl).
//
// Replaces the splats' own visibility pass (their opaque cores), which cannot tell a
// neighbour of the same surface from a surface behind at a contour.
#include <array>
#include <span>
#include <vector>

#include "core/math.h"
#include "gpu/buffer.h"
#include "gpu/device.h"
#include "gpu/device_handle.h"
#include "gpu/image.h"
#include "gpu/pipeline.h"
#include "gpu/sampled_image_set.h"
#include "render/frame_inputs.h"
#include "render/gpu_use.h"

namespace pbdsplat::render {

// Distance along the view axis, 0 where no surface is.
constexpr VkFormat k_occluder_format = VK_FORMAT_R32_SFLOAT;

// How finely a detailed model's surface is drawn as occluders on this device, as a share of the
// occluders' tolerance (scene/stages/fine_surface.h, FineTriangles::simplify_error); 0: every
// triangle. A CPU rasteriser pays per triangle: on Lavapipe the bunny's 69,451 triangles took
// 21-22 ms of a 1280x720 frame, 8,869 within a tenth of the tolerance 7.6-9.0 ms, and `check`'s
// figures moved under 0.5 % (docs/BENCHMARKS.md, "Mesh occluders"). A GPU draws the full surface
// for next to nothing, and the 33-45 ms that simplifying the bunny takes after a cut would be a
// hitch there.
float occluder_simplify_share(const gpu::DeviceCaps& caps);

class OccluderPass {
public:
    // `slots`: copies of the mesh buffers, one per frame in flight.
    static core::Result<OccluderPass> create(gpu::Context& ctx, uint32_t width, uint32_t height, uint32_t slots, VkFormat depth_format);
    OccluderPass() = default;

    // Copies the mesh into `slot`'s host-visible buffers (grown as a cut adds vertices); call
    // while no frame using that slot is in flight. The first `one_sided` triangles close solids,
    // wound out of them, whose inside never shows: drawn front faces only (a closed body's back
    // faces lie behind its front ones at every pixel, so only the work and the gaps where a cut
    // face meets its shell differ); the rest both sides (an open body's inside occludes too).
    core::Status set_mesh(std::span<const Vec4f> positions, std::span<const std::array<uint32_t, 3>> triangles, uint32_t slot,
                          size_t one_sided = 0);
    // Draws `slot`'s mesh into `depth` (loaded and stored, in attachment layout) and the distance
    // image (cleared); `push`: how far depth is pushed back, world units.
    void record(VkCommandBuffer cmd, const Camera& camera, float push, VkImageView depth, uint32_t slot) const;

    const gpu::Image& image() const { return image_; }
    // The distance image at binding 0 (SHADER_READ_ONLY layout), for the accumulation's set 1,
    // read by the stages `sampled()` says (the geometry and mesh paths' front stages too).
    VkDescriptorSetLayout set_layout() const { return sampled_.layout(); }
    Use sampled() const { return sampled_use_; }
    VkDescriptorSet set() const { return sampled_.set(); }

private:
    gpu::Context* ctx_ = nullptr;
    struct Slot {
        gpu::Buffer vertices, indices;
        uint32_t index_count = 0;
        uint32_t one_sided_indices = 0;  // the leading indices drawn front faces only
    };
    std::vector<Slot> slots_;
    gpu::Image image_;
    gpu::SampledImageSet sampled_;
    Use sampled_use_;
    gpu::PipelineLayout layout_;
    gpu::Pipeline pipeline_, one_sided_;
    VkExtent2D extent_{};
};

} // namespace pbdsplat::render
