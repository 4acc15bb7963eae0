#include "scene/stages/solid_pieces.h"

#include <algorithm>

namespace pbdsplat::scene {

std::vector<uint8_t> solid_pieces(const sim::SoftBody& body, const splat::CutFaces* faces) {
    std::vector<uint8_t> solid(body.pieces, 0);
    for (const sim::VolumeConstraint& v : body.volumes) {
        if (v.piece >= body.pieces || v.leak > 0.0f || !(v.rest_volume > 0.0)) continue;
        const bool closed = std::all_of(v.cap_loops.begin(), v.cap_loops.end(), [&](const std::vector<uint32_t>& loop) {
            return faces && faces->triangles_of(loop) != nullptr;
        });
        solid[v.piece] = closed ? 1 : 0;
    }
    return solid;
}

Solids which_solid(const std::vector<uint8_t>& solid) {
    const size_t n = size_t(std::count(solid.begin(), solid.end(), uint8_t(1)));
    return n == 0 ? Solids::none : n < solid.size() ? Solids::some : Solids::all;
}

SolidOrder order_solids_first(const sim::SoftBody& body, const std::vector<uint8_t>& solid, std::vector<mesh::Triangle>& triangles,
                              const surface::BoundaryParticles* fine_vertices) {
    const Solids kind = which_solid(solid);
    if (kind == Solids::none) return {};
    if (kind == Solids::all) return {true, triangles.size()};
    // A fine triangle's piece is that of the body triangle its first corner rides on; past the
    // fine vertices come the body's particles (FineCopies).
    const auto piece_of = [&](const mesh::Triangle& t) {
        const size_t fine = fine_vertices ? fine_vertices->size() : 0;
        const uint32_t i = t[0] < fine ? body.triangles[fine_vertices->triangle[t[0]]][0] : uint32_t(t[0] - fine);
        return body.piece_of_particle[i];
    };
    std::vector<mesh::Triangle> open;
    size_t front = 0;
    for (const mesh::Triangle& t : triangles) {
        const uint32_t p = piece_of(t);
        if (p < solid.size() && solid[p]) triangles[front++] = t;
        else open.push_back(t);
    }
    std::copy(open.begin(), open.end(), triangles.begin() + long(front));
    return {false, front};
}

} // namespace pbdsplat::scene
