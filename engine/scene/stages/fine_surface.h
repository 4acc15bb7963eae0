#pragma once
// The model's full-resolution surface as the simulation mesh carries it now (a decimated body
// under a fine surface): its vertices embedded in the simulation triangles like the samples,
// made on the first call (only coverage checks and mesh occluders ask). Triangles a cut or tear
// tore across (corners on different pieces, or on body triangles torn apart between them, or an
// edge stretched past 3x) are left out.
#include <optional>
#include <vector>

#include "mesh/triangle_mesh.h"
#include "sim/soft_body.h"
#include "surface/boundary_particles.h"

namespace pbdsplat::scene {

void deformed_fine_surface(const sim::SoftBody& body, const mesh::TriangleMesh& fine, std::optional<surface::BoundaryParticles>& fine_vertices,
                           std::vector<Vec4f>& x, std::vector<mesh::Triangle>& triangles);

} // namespace pbdsplat::scene
