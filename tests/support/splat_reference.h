#pragma once
// A plain CPU rendering of splats, written from the paper's equations and not from the shaders,
// for the GPU paths to be compared against: per pixel, the view ray meets each splat's quad
// plane (eq. 15's centre depth); the footprint is the projected covariance of eq. 14's axes
// through the perspective Jacobian at the centre, diagonalised by Eigen; the paper's disc keeps
// the unit ellipse of eqs. 19-23, the Gaussian its falloff down to alpha 1/255. Lighting is left
// out (flat albedo): the reference checks where and how opaque, the goldens check the shading.
#include <array>
#include <vector>

#include "core/image.h"
#include "render/frame_inputs.h"
#include "splat/gaussian_record.h"

namespace pbdsplat::test {

struct ReferencePixel {
    Vec3f color = Vec3f::Zero();
    // How close the pixel centre lies to a disc's rim (|r - 1| of the nearest rim among the
    // splats that decide it): where it is tiny, float rounding may flip the GPU's choice.
    float rim_margin = 1e9f;
};

// `frame` must have flat lighting (environment off, no key light, no specular, ambient 1):
// a splat's colour is then its albedo. Paper discs: the nearest covering disc wins. Gaussian:
// composited in the records' order ("over", premultiplied), summed (additive) or normalised
// (round splats facing the eye; rim_margin is then how near a pixel lies to the edge of an
// opaque core, which decides what counts as the front surface).
// `shapes` (one per record, or empty): anisotropic axes, projected by EWA (J W Sigma W^T J^T)
// plus a 0.3 pixel^2 low-pass for the Gaussian, as 3D Gaussian splatting does; the paper's disc
// has none but stays at least a pixel wide seen edge-on, as the shaders draw it.
// The surface mesh that hides what lies behind it (frame.style.mesh_occluders): a fragment is
// kept where the mesh is seen at its pixel, from twice occluder_tolerance in front of it to
// occluder_tolerance behind (along the view axis), and next to where the mesh is seen (a pixel
// of rim past the outline). The mesh's depth comes from casting each pixel's ray at its
// triangles, not from a raster; rim_margin is 0 where a pixel or a neighbour lies on the mesh's
// outline, or a splat near the tolerance's ends.
struct OccluderMesh {
    std::vector<Vec4f> x;
    std::vector<std::array<uint32_t, 3>> triangles;
};

std::vector<ReferencePixel> render_reference(const std::vector<splat::GaussianRecord>& records,
                                             const render::FrameInputs& frame, uint32_t width, uint32_t height,
                                             const std::vector<splat::GaussianShape>& shapes = {},
                                             const OccluderMesh* occluders = nullptr);

} // namespace pbdsplat::test
