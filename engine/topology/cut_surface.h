#pragma once
// The surface a cut follows (paper section 5.7): a plane, optionally restricted to part of it.
// A screen-space stroke defines the plane through the eye holding the view rays of its two
// ends, restricted to what projects inside the stroke; scripts may use a whole world plane.
#include <cstdint>
#include <algorithm>
#include <functional>
#include <vector>

#include "core/math.h"
#include "core/result.h"
#include "sim/soft_body.h"

namespace pbdsplat::topology {

struct CutSurface {
    Vec3f point = Vec3f::Zero();
    Vec3f normal = Vec3f::UnitX();  // unit; the positive side is where normal . (x - point) > 0
    // Which points of the plane the cut reaches; empty means all of it. Called with points of
    // the plane only (edge crossings, vertices lying on the plane).
    std::function<bool(const Vec3f&)> inside;
    // Which particles the cut may touch, ascending; empty means all. A tear opens a slit in the
    // torn vertex's own neighbourhood: on a crumpled shell, other layers pass through the same
    // ball in space, and a purely geometric reach would cut them all. A listed cut also costs
    // only its list: the cut looks at nothing else of the body.
    std::vector<uint32_t> particles;

    float distance(const Vec3f& x) const { return normal.dot(x - point); }
    bool reaches(const Vec3f& x) const { return !inside || inside(x); }
    bool may_touch(uint32_t particle) const { return particles.empty() || std::binary_search(particles.begin(), particles.end(), particle); }
};

// A whole world plane through `point` with normal `normal` (need not be unit length).
core::Result<CutSurface> plane_cut(const Vec3f& point, const Vec3f& normal);

// The band swept by the screen segment a-b (pixels of a `screen`-sized view, y down) along the
// view rays of the camera `view_proj` placed at `eye`.
core::Result<CutSurface> screen_cut(const Mat4f& view_proj, const Vec3f& eye, const Vec2f& screen, const Vec2f& a,
                                    const Vec2f& b);

// A ball-limited plane: what tearing uses to open a short slit across one edge.
CutSurface local_cut(const Vec3f& point, const Vec3f& unit_normal, float radius);

// A scalpel: local_cut at `particle`, limited to the surface connected to it inside the ball
// (and the ring just past it, so edges leaving the ball can be crossed). Other layers or pieces
// that pass through the ball are not cut, and the cut costs the region, not the body.
CutSurface local_cut_on(const sim::SoftBody& body, uint32_t particle, const Vec3f& unit_normal, float radius);

} // namespace pbdsplat::topology
