#pragma once
// How evenly a point set is spaced: what `pbdsplat check` and the density tests measure the
// boundary particles by.
#include <cstddef>
#include <cstdint>
#include <span>

#include "core/math.h"

namespace pbdsplat::surface {

// Nearest-neighbour spacing of a point set, for the density goals: the share of points whose
// nearest neighbour lies within [low, high] (both in units of h), and quantiles. Only the first
// `measured` points are measured (all by default); the rest count as their neighbours only.
// With `normals` (one per point), a neighbour counts only on the same side of the surface
// (normals within 60 degrees): across a sharp fold the sheets' samples come closer in space than
// along the surface, where their spacing is.
struct SpacingReport {
    size_t points = 0;
    float within = 0.0f;  // share in [low h, high h]
    float p05 = 0.0f, median = 0.0f, p95 = 0.0f;  // in units of h
};
struct SpacingQuery {
    float low = 0.7f, high = 1.4f;
    size_t measured = SIZE_MAX;
    std::span<const Vec3f> normals;
};
SpacingReport spacing_report(std::span<const Vec3f> points, float h, const SpacingQuery& query);
inline SpacingReport spacing_report(std::span<const Vec3f> points, float h) { return spacing_report(points, h, SpacingQuery{}); }

} // namespace pbdsplat::surface
