#pragma once
// Where a textured model's texture lies at a point of its surface, for a splat there that reads
// the texture under each of its pixels (scene/stages/paint.h, splat/texcoords.h): the
// coordinates at the point and their gradients along the surface at rest, the texture, the
// colour it multiplies, and how far from the coordinates the splat may read before it would
// cross a seam.
#include <cstdint>

#include "core/math.h"

namespace pbdsplat::mesh {

struct SurfaceTexcoord {
    Vec2f uv = Vec2f::Zero();
    Vec3f du = Vec3f::Zero(), dv = Vec3f::Zero();  // world gradients at rest (the body's rest frame)
    Vec3f tint = Vec3f::Ones();
    int32_t texture = -1;  // -1: none; the point keeps its painted colour alone
    float reach = 0.0f;  // how far from the point (world units at rest) its splat may read
};

// The texture at a point a fraction t of the way from a to b (an edge a cut or tear splits):
// a's texture, the coordinates and gradients between, the shorter reach.
SurfaceTexcoord lerp(const SurfaceTexcoord& a, const SurfaceTexcoord& b, float t);

} // namespace pbdsplat::mesh
