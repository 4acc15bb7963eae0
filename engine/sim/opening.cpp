#include "sim/opening.h"

#include <algorithm>

#include "mesh/topology.h"
#include "sim/volume.h"

namespace pbdsplat::sim {
namespace {

// The face drawn over a boundary loop: the cap loop of the same particles (as the volume
// constraint keeps it, wound out of its piece, from a corner of its own).
const std::vector<mesh::Triangle>* drawn_face(const SoftBody& body, const std::vector<uint32_t>& loop, const FaceLookup& faces) {
    if (!faces || loop.empty()) return nullptr;
    const uint32_t least = *std::min_element(loop.begin(), loop.end());
    for (const VolumeConstraint& v : body.volumes)
        for (const std::vector<uint32_t>& cap : v.cap_loops)
            if (cap.size() == loop.size() && std::find(cap.begin(), cap.end(), least) != cap.end()) return faces(cap);
    return nullptr;
}

} // namespace

OpeningReport opening_report(const SoftBody& body, const FaceLookup& faces) {
    OpeningReport out;
    if (body.triangles.empty()) return out;
    double six_v = 0.0, edges = 0.0;
    for (const mesh::Triangle& t : body.triangles) {
        const Vec3d a = body.particles.x[t[0]].head<3>().cast<double>(), b = body.particles.x[t[1]].head<3>().cast<double>(),
                    c = body.particles.x[t[2]].head<3>().cast<double>();
        six_v += a.dot(b.cross(c));
        for (int k = 0; k < 3; ++k) edges += double((body.rest_positions[t[k]] - body.rest_positions[t[(k + 1) % 3]]).norm());
    }
    const double mean_edge = edges / double(3 * body.triangles.size());
    const auto p3 = [&](uint32_t i) { return body.particles.x[i].head<3>().cast<double>(); };
    for (std::vector<uint32_t>& loop : mesh::boundary_loops(body.triangles, body.particle_count())) {
        for (size_t k = 0; k < loop.size(); ++k)
            out.open_length += double((body.rest_positions[loop[k]] - body.rest_positions[loop[(k + 1) % loop.size()]]).norm());
        // The loops run along their triangles' open edges; a cap runs against them.
        std::reverse(loop.begin(), loop.end());
        if (const std::vector<mesh::Triangle>* face = drawn_face(body, loop, faces)) {
            for (const mesh::Triangle& t : *face) six_v += p3(t[0]).dot(p3(t[1]).cross(p3(t[2])));
        } else {
            six_v += cap_six_volume<float>(loop, body.particles.x);
        }
    }
    out.volume = six_v / 6.0;
    out.open_length = mean_edge > 0.0 ? out.open_length / mean_edge : 0.0;
    return out;
}

} // namespace pbdsplat::sim
