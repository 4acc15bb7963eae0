#include "mesh/surface_texcoord.h"

#include <algorithm>

namespace pbdsplat::mesh {

SurfaceTexcoord lerp(const SurfaceTexcoord& a, const SurfaceTexcoord& b, float t) {
    SurfaceTexcoord out = a;
    if (a.texture < 0 || b.texture != a.texture) return out;  // across materials: one side's
    out.uv = a.uv + t * (b.uv - a.uv);
    out.du = a.du + t * (b.du - a.du);
    out.dv = a.dv + t * (b.dv - a.dv);
    out.tint = a.tint + t * (b.tint - a.tint);
    out.reach = std::min(a.reach, b.reach);
    return out;
}

} // namespace pbdsplat::mesh
