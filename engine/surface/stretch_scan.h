#pragma once
// The density control's scan of every triangle on every frame (surface/density.h): each
// triangle's squared largest and smallest stretch (the eigenvalues of F^T F), and which
// triangles need the per-triangle logic this frame. Several triangles at a time in SIMD lanes:
// four with SSE, eight where the processor has AVX (asked at run time). Each lane does the same
// operations in the same order either way (no fused multiply-add), so both give the same bits.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/math.h"
#include "mesh/triangle_mesh.h"

namespace pbdsplat::surface {

struct StretchScan {
    std::span<const Vec4f> x;  // the particles (w ignored)
    std::span<const mesh::Triangle> triangles;
    // Per block of four triangles, their inverse rest frames' a entries, then c, b, d (four each).
    const float* rest_lanes = nullptr;
    float* stretch2 = nullptr;  // out, per triangle
    float* squeeze2 = nullptr;  // out, per triangle
    // Per triangle: the 5 % change bounds, the squared stretches when last sampled, and the
    // frames in a row past a threshold (surface/density.h).
    const float *shrank_large2 = nullptr, *shrank_small2 = nullptr, *grew_large2 = nullptr, *grew_small2 = nullptr;
    const float *reference2 = nullptr, *reference_squeeze2 = nullptr;
    const int8_t* beyond = nullptr;
    float grow2 = 1.0f, shrink2 = 1.0f, squash2 = 1.0f, unsquash2 = 1.0f;  // the thresholds, squared
};

enum class ScanLanes { best, four, eight };

// Whether this processor (and its operating system) runs the eight-lane scan.
bool eight_lanes_available();

// Scans the first triangles in whole blocks of four: writes their stretches and appends to
// `busy`, in ascending order, each one that changed by 5 %, is past a threshold, was counting
// frames past one, or measured NaN. Returns how many it scanned (a multiple of four); the
// remaining few are the caller's. `lanes`: four or eight forced (eight where available), for
// the test that holds the two to the same bits.
size_t scan_stretches(const StretchScan& scan, std::vector<uint32_t>& busy, ScanLanes lanes = ScanLanes::best);

} // namespace pbdsplat::surface
