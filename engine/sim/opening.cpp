#include "sim/opening.h"

#include <algorithm>

#include "mesh/topology.h"
#include "sim/volume.h"

namespace pbdsplat::sim {

OpeningReport opening_report(const SoftBody& body) {
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
    for (std::vector<uint32_t>& loop : mesh::boundary_loops(body.triangles, body.particle_count())) {
        for (size_t k = 0; k < loop.size(); ++k)
            out.open_length += double((body.rest_positions[loop[k]] - body.rest_positions[loop[(k + 1) % loop.size()]]).norm());
        // The loops run along their triangles' open edges; a cap runs against them.
        std::reverse(loop.begin(), loop.end());
        six_v += cap_six_volume<float>(loop, body.particles.x);
    }
    out.volume = six_v / 6.0;
    out.open_length = mean_edge > 0.0 ? out.open_length / mean_edge : 0.0;
    return out;
}

} // namespace pbdsplat::sim
