#include "sim/penetration.h"

#include <algorithm>
#include <map>
#include <vector>

namespace pbdsplat::sim {

Penetration deepest_penetration(const SoftBody& body, const FaceLookup& faces) {
    Penetration deepest;
    const std::vector<ClosedSurface> surfaces = closed_surfaces(body, false, faces);
    const bool rest_known = body.rest_positions.size() == body.particle_count();
    const std::vector<ClosedSurface> at_rest = rest_known ? closed_surfaces(body, true, faces) : std::vector<ClosedSurface>{};
    const bool parts_known = body.part_of_particle.size() == body.particle_count();
    // Per (part, surface): whether some particle of the part lay inside that piece at rest (the
    // part sits in another in the file: suzanne's eyes, a teapot's lid). Contact leaves such parts
    // to their own shells (sim/contact.h), so how they settle into each other is not measured.
    std::map<std::pair<uint32_t, size_t>, bool> overlapped;  // (part, surface) -> decided
    std::vector<uint32_t> part_of_piece(body.pieces, UINT32_MAX);
    if (parts_known)
        for (size_t j = 0; j < body.particle_count(); ++j)
            if (body.piece_of_particle[j] < body.pieces) part_of_piece[body.piece_of_particle[j]] = body.part_of_particle[j];
    // The other side of a cut is the same part: never left out, however its rim lies on the face.
    const auto overlapped_at_rest = [&](uint32_t part, size_t k) {
        if (part == part_of_piece[at_rest[k].piece]) return false;
        const auto [it, fresh] = overlapped.try_emplace({part, k}, false);
        if (fresh)
            for (size_t j = 0; j < body.particle_count() && !it->second; ++j)
                it->second = body.part_of_particle[j] == part && body.piece_of_particle[j] != at_rest[k].piece &&
                             inside(at_rest[k], body.rest_positions[j]);
        return it->second;
    };
    for (size_t k = 0; k < surfaces.size(); ++k) {
        const ClosedSurface& s = surfaces[k];
        for (size_t i = 0; i < body.particle_count(); ++i) {
            if (body.piece_of_particle[i] == s.piece) continue;
            const Vec3f p = xyz(body.particles.x[i]);
            if (!inside(s, p)) continue;
            // A particle that lay inside this piece at rest has not come through it; nor has a
            // part that lay partly inside it.
            if (rest_known && inside(at_rest[k], body.rest_positions[i])) continue;
            if (rest_known && parts_known && overlapped_at_rest(body.part_of_particle[i], k)) continue;
            const float d = distance_to(s, p);
            if (d > deepest.depth) deepest = {d, uint32_t(i), s.piece};
        }
    }
    return deepest;
}

} // namespace pbdsplat::sim
