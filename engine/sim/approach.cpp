#include "sim/approach.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <vector>

namespace pbdsplat::sim {

template <class Real>
uint32_t approach_substeps(const SoftBodyT<Real>& body, float dt, float edge, uint32_t most) {
    const size_t pieces = body.pieces;
    if (pieces < 2 || pieces > k_approach_pieces || !(edge > 0.0f) || !(dt > 0.0f) || most <= 1) return 1;
    // Each piece's box and the mean velocity of its particles: pieces moving together (the parts
    // of an inflating balloon, a stack falling as one) or apart do not close on each other,
    // however fast.
    std::vector<Eigen::AlignedBox3f> box(pieces);
    std::vector<Vec3f> velocity(pieces, Vec3f::Zero());
    std::vector<uint32_t> count(pieces, 0);
    for (size_t i = 0; i < body.particle_count(); ++i) {
        const uint32_t k = body.piece_of_particle[i];
        if (k >= pieces) continue;
        box[k].extend(xyz(body.particles.x[i]));
        velocity[k] += xyz(body.particles.v[i]);
        ++count[k];
    }
    for (size_t k = 0; k < pieces; ++k)
        if (count[k]) velocity[k] /= float(count[k]);
    float closing = 0.0f;  // the most two pieces whose paths meet close on each other in a frame, in metres
    for (size_t a = 0; a < pieces; ++a) {
        if (box[a].isEmpty()) continue;
        for (size_t b = a + 1; b < pieces; ++b) {
            if (box[b].isEmpty()) continue;
            // Closing along the line between the boxes' centres; parting (a torn patch pulled
            // away by the hand) needs nothing.
            const Vec3f apart = box[b].center() - box[a].center();
            const float gap = apart.norm();
            const float both = (gap > 0.0f ? (velocity[a] - velocity[b]).dot(apart / gap) : (velocity[a] - velocity[b]).norm()) * dt;
            if (!(both > closing)) continue;
            if (box[a].exteriorDistance(box[b]) <= both) closing = both;
        }
    }
    const float need = closing / (0.5f * edge);
    if (!(need > 1.0f)) return 1;
    if (!(need < float(most))) return std::bit_floor(most);
    return std::min(std::bit_ceil(uint32_t(std::ceil(need))), std::bit_floor(most));
}

template <class Real>
uint32_t frame_substeps(const SolverSettings& s, const SoftBodyT<Real>& body, const ContactSolverT<Real>& contact, float dt,
                        uint32_t max_sweeps) {
    if (!s.contact.enabled) return s.substeps;
    const uint32_t room = max_sweeps / std::max(1u, s.iterations);  // substeps within the sweeps
    uint32_t n = s.substeps;
    if (contact.stacked()) n = std::max(n, std::min(s.contact.substeps, room));
    if (!approach_steps(s, body)) return n;
    return std::max(n, approach_substeps(body, dt, contact.scale().edge, std::min(k_max_approach_substeps, room)));
}

template uint32_t approach_substeps<float>(const SoftBodyT<float>&, float, float, uint32_t);
template uint32_t approach_substeps<double>(const SoftBodyT<double>&, float, float, uint32_t);
template uint32_t frame_substeps<float>(const SolverSettings&, const SoftBodyT<float>&, const ContactSolverT<float>&, float, uint32_t);
template uint32_t frame_substeps<double>(const SolverSettings&, const SoftBodyT<double>&, const ContactSolverT<double>&, float, uint32_t);

} // namespace pbdsplat::sim
