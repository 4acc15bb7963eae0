#pragma once
// The binary PLY layout that 3D Gaussian splatting viewers read: per Gaussian x y z, nx ny nz,
// f_dc_0..2 (degree-0 spherical-harmonic colour), f_rest_* (degrees 1-3, optional), opacity as
// a logit, scale_0..2 as natural logs, rot_0..3 as a quaternion w x y z. Little-endian floats.
#include <span>
#include <string>
#include <vector>

#include "core/result.h"
#include "splat/gaussian_record.h"
#include "splat/normal_estimate.h"

namespace pbdsplat::splat {

// Which way is up in the file. 3DGS captures, and the viewers and converters that read them,
// are y-down (OpenCV cameras); pbdsplat's world is y-up. Between the two is a half turn about x,
// (x, y, z) -> (x, -y, -z), the same both ways: positions, normals, rotations and the odd
// spherical-harmonic coefficients turn with it. Not a mirror: handedness is kept.
enum class PlyUp { y, minus_y };

struct PlyWriteOptions {
    PlyUp up = PlyUp::minus_y;  // the 3DGS convention, so other viewers show the body upright
    uint32_t sh_degree = 0;     // f_rest columns for degrees 1..d (zeros: we have none); 0 writes none
};

// The header for `count` Gaussians, exactly as written.
std::string ply_header(size_t count, uint32_t sh_degree = 0);

// `shapes` (one per record, or empty for round splats): each Gaussian's covariance written as
// the rotation and scales of its principal axes.
core::Status write_ply(const std::string& path, std::span<const GaussianRecord> records,
                       std::span<const GaussianShape> shapes = {}, const PlyWriteOptions& options = {});

// What a 3DGS PLY holds, as the renderer takes it: the records, and the axes of every Gaussian
// (rotation rot_0..3 = w x y z times the scales) when any of them is not round; empty when all
// are (their scales agree within 2 %), so round files cost nothing extra.
// Degrees 1-3 of the colour (f_rest_*) likewise, when the file has any that are not zero.
struct PlyGaussians {
    std::vector<GaussianRecord> records;  // scale: the largest axis
    std::vector<GaussianShape> shapes;
    std::vector<GaussianSH> sh;
    uint32_t sh_degree = 0;  // 1-3 when `sh` is not empty
    size_t dropped_nonfinite = 0;  // Gaussians with a NaN or infinite value, left out
    size_t missing_normals = 0;    // no normals in the file, or zero ones: estimated (splat/normal_estimate.h)
    NormalEstimate estimated;      // how they were; the unresolved face +z in the file's frame
    bool normals_estimated = false;  // false: MissingNormals::leave, or none missing
};
// Normals a file lacks matter only to lighting: a capture drawn as trained (unlit) skips their
// estimate, which is most of a large file's load (a neighbour search per Gaussian).
enum class MissingNormals { estimate, leave };
// `missing`: leave keeps +z in the file's frame where a normal is missing (still counted).
core::Result<PlyGaussians> read_ply_gaussians(const std::string& path, PlyUp up = PlyUp::minus_y,
                                              MissingNormals missing = MissingNormals::estimate);

// The records alone (properties in any order; normals, f_rest and rot optional): an anisotropic
// Gaussian becomes a round one with its largest scale.
core::Result<std::vector<GaussianRecord>> read_ply(const std::string& path, PlyUp up = PlyUp::minus_y);

} // namespace pbdsplat::splat
