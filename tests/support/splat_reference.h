#pragma once
// A plain CPU rendering of splats, written from the paper's equations and not from the shaders,
// for the GPU paths to be compared against: per pixel, the view ray meets each splat's quad
// plane (eq. 15's centre depth); the footprint is the projected covariance of eq. 14's axes
// through the perspective Jacobian at the centre, diagonalised by Eigen; the paper's disc keeps
// the unit ellipse of eqs. 19-23, the Gaussian its falloff down to alpha 1/255. Lighting is left
// out (flat albedo): the reference checks where and how opaque, the goldens check the shading.
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
std::vector<ReferencePixel> render_reference(const std::vector<splat::GaussianRecord>& records,
                                             const render::FrameInputs& frame, uint32_t width, uint32_t height,
                                             const std::vector<splat::GaussianShape>& shapes = {});

} // namespace pbdsplat::test
