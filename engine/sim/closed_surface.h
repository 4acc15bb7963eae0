#pragma once
// A closed piece's surface as plain triangles (its own and those spanning its cap loops), and
// whether a point lies inside it by the generalised winding number: what penetration measures
// against, and what tells at load that one part of a body lies wholly inside another.
#include <cstdint>
#include <functional>
#include <vector>

#include "sim/soft_body.h"

namespace pbdsplat::sim {

struct Corner3 {
    Vec3f a, b, c;
};

struct ClosedSurface {
    uint32_t piece = 0;
    std::vector<Corner3> triangles;
    Eigen::AlignedBox3f box;
};

// A cap loop's triangles as drawn and met (over the body's particles), or null: then the loop's
// least-area span.
using FaceLookup = std::function<const std::vector<mesh::Triangle>*(const std::vector<uint32_t>& loop)>;

// One surface per closed piece (a volume constraint no burst opened), where the particles are
// now or, with `rest`, where they lay at rest.
std::vector<ClosedSurface> closed_surfaces(const SoftBody& body, bool rest, const FaceLookup& faces = {});

// The generalised winding number at `p` exceeds one half.
bool inside(const ClosedSurface& s, const Vec3f& p);
float distance_to(const ClosedSurface& s, const Vec3f& p);

} // namespace pbdsplat::sim
