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

core::Status write_ply(const std::string& path, std::span<const GaussianRecord> records);

// Reads a 3DGS PLY (properties in any order; normals and f_rest optional). Splats are
// isotropic here: an anisotropic Gaussian becomes one with its largest scale, and its rotation
// is dropped.
core::Result<std::vector<GaussianRecord>> read_ply(const std::string& path);

} // namespace pbdsplat::splat
