#pragma once
// The binary PLY layout that 3D Gaussian splatting viewers read: per Gaussian x y z, nx ny nz,
// f_dc_0..2 (degree-0 spherical-harmonic colour), f_rest_0..44 (all zero here), opacity as a
// logit, scale_0..2 as natural logs, rot_0..3 as a quaternion w x y z. Little-endian floats,
// no comments in the header.
#include <span>
#include <string>
#include <vector>

#include "core/result.h"
#include "splat/gaussian_record.h"

namespace pbdsplat::splat {

// The header for `count` Gaussians, exactly as written.
std::string ply_header(size_t count);

// `shapes` (one per record, or empty for round splats): each Gaussian's covariance written as
// the rotation and scales of its principal axes.
core::Status write_ply(const std::string& path, std::span<const GaussianRecord> records,
                       std::span<const GaussianShape> shapes = {});

// What a 3DGS PLY holds, as the renderer takes it: the records, and the axes of every Gaussian
// (rotation rot_0..3 = w x y z times the scales) when any of them is not round; empty when all
// are (their scales agree within 2 %), so round files cost nothing extra.
// Degrees 1-3 of the colour (f_rest_*) likewise, when the file has any that are not zero.
struct PlyGaussians {
    std::vector<GaussianRecord> records;  // scale: the largest axis
    std::vector<GaussianShape> shapes;
    std::vector<GaussianSH> sh;
    uint32_t sh_degree = 0;  // 1-3 when `sh` is not empty
};
core::Result<PlyGaussians> read_ply_gaussians(const std::string& path);

// The records alone (properties in any order; normals, f_rest and rot optional): an anisotropic
// Gaussian becomes a round one with its largest scale.
core::Result<std::vector<GaussianRecord>> read_ply(const std::string& path);

} // namespace pbdsplat::splat
