#pragma once
// Which pieces are solids whose inside never shows, so that the mesh occluders may draw their
// surface front faces only (render/occluder_pass.h): half the occluder pass's triangles, and no
// inside wall showing through where a cut face meets its shell.
#include <cstdint>
#include <vector>

#include "mesh/triangle_mesh.h"
#include "sim/soft_body.h"
#include "splat/cut_faces.h"
#include "surface/boundary_particles.h"

namespace pbdsplat::scene {

// Per piece: a volume constraint that holds its gas (no leak), wound out of the piece (positive
// rest volume), and every cap loop closed by a drawn cut face (`faces`; null: none drawn). A
// tear's slit, a burst, a model's own hole, a sheet without a volume, or a model wound inside
// out leaves its piece drawn both sides.
std::vector<uint8_t> solid_pieces(const sim::SoftBody& body, const splat::CutFaces* faces);

// The occluders' surface put in draw order: `triangles`, the body's surface (its own triangles,
// or the fine surface's, whose vertices `fine_vertices` embeds in the body's triangles), to which
// the caller then appends the cut faces. Where some pieces are solid and some not, the solids'
// triangles are moved to the front, each group in its order, and the faces drawn both sides
// with the open ones.
struct SolidOrder {
    bool all = false;    // every piece solid: every triangle, faces included, one-sided
    size_t leading = 0;  // else the leading triangles that are
    size_t one_sided(size_t total) const { return all ? total : leading; }
};
// `solid`: solid_pieces' answer.
SolidOrder order_solids_first(const sim::SoftBody& body, const std::vector<uint8_t>& solid, std::vector<mesh::Triangle>& triangles,
                              const surface::BoundaryParticles* fine_vertices);
// Whether no piece, some or all are solid (order_solids_first moves triangles only for some).
enum class Solids { none, some, all };
Solids which_solid(const std::vector<uint8_t>& solid);

} // namespace pbdsplat::scene
