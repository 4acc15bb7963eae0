#include "topology/volume_policy.h"

#include <cmath>


#include "mesh/topology.h"
#include "sim/volume.h"

namespace pbdsplat::topology {
namespace {
// A piece too thin or too small to hold air: a flake torn off a shell, a sliver of a few
// triangles. Its capped volume is nearly zero against its area, so a volume constraint on it
// has a tiny gradient and a projection step of C / |grad|^2 that flings its particles away: it
// gets none and moves as cloth. A sphere scores V / A^1.5 = 0.094, a shallow dome of height
// 0.05 r about 0.014.
bool holds_air(const sim::VolumeConstraint& v, double volume, const sim::Vec4Array& x) {
    if (v.triangles.size() < 12) return false;
    double area = 0.0;
    for (const auto& t : v.triangles)
        area += 0.5 * double((x[t[1]] - x[t[0]]).head<3>().cross((x[t[2]] - x[t[0]]).head<3>()).norm());
    return area > 0.0 && std::abs(volume) / std::pow(area, 1.5) >= 0.01;
}
} // namespace

size_t apply_volume_policy(sim::SoftBody& b, VolumePolicy policy, float leak, std::span<const int32_t> old_of_triangle,
                           std::span<OldVolume> old, std::span<const uint8_t> touched, std::vector<uint32_t>& rebuilt) {
    rebuilt.clear();
    std::vector<uint32_t> comp;
    const uint32_t nc = mesh::vertex_components(b.triangles, b.particle_count(), comp);
    if (old.empty()) return nc;
    std::vector<int32_t> from(nc, -1);
    for (size_t t = 0; t < b.triangles.size(); ++t)
        if (from[comp[t]] < 0) from[comp[t]] = old_of_triangle[t];
    // The volume of each touched constraint just before the change: its triangles still name
    // the old corners, whose positions did not move.
    for (size_t k = 0; k < old.size(); ++k)
        if (touched[k]) old[k].now = sim::constraint_volume<float>(b.volumes[k], b.particles.x);
    std::vector<sim::VolumeConstraint> pieces(nc);
    std::vector<uint8_t> remake(nc, 0);
    std::vector<mesh::Triangle> remade_triangles;  // of all remade pieces, for their boundary loops
    for (uint32_t c = 0; c < nc; ++c) remake[c] = from[c] >= 0 && touched[size_t(from[c])];
    for (size_t t = 0; t < b.triangles.size(); ++t)
        if (remake[comp[t]]) pieces[comp[t]].triangles.push_back(b.triangles[t]), remade_triangles.push_back(b.triangles[t]);
    if (!remade_triangles.empty()) {
        std::vector<uint32_t> comp_of_vertex(b.particle_count(), UINT32_MAX);
        for (size_t t = 0; t < b.triangles.size(); ++t)
            if (remake[comp[t]])
                for (uint32_t v : b.triangles[t]) comp_of_vertex[v] = comp[t];
        for (auto& loop : mesh::boundary_loops(remade_triangles, b.particle_count()))
            pieces[comp_of_vertex[loop[0]]].cap_loops.push_back(std::move(loop));
    }

    std::vector<double> now(nc, 0.0);
    std::vector<uint32_t> pieces_of_old(old.size(), 0);
    for (uint32_t c = 0; c < nc; ++c) {
        if (from[c] < 0) continue;
        if (remake[c]) now[c] = sim::constraint_volume<float>(pieces[c], b.particles.x);
        ++pieces_of_old[size_t(from[c])];
    }
    std::vector<sim::VolumeConstraint> out;
    for (uint32_t c = 0; c < nc; ++c) {
        if (from[c] < 0) continue;
        if (!remake[c]) {  // a piece the change did not reach keeps its constraint as it was
            out.push_back(std::move(b.volumes[size_t(from[c])]));
            continue;
        }
        const OldVolume& parent = old[size_t(from[c])];
        sim::VolumeConstraint& v = pieces[c];
        v.pressure = parent.pressure;
        v.compliance = parent.compliance;
        v.leak = parent.leak;
        const bool unchanged = pieces_of_old[size_t(from[c])] == 1 && v.triangles.size() == parent.triangles &&
                               v.cap_loops.size() == parent.cap_loops;
        if (unchanged) {
            v.rest_volume = parent.rest_volume;
        } else if (policy == VolumePolicy::rebase) {
            v.rest_volume = now[c] / double(v.pressure);  // the target is the volume it has now
        } else {
            const double before = parent.now;
            v.rest_volume = before > 0.0 ? parent.rest_volume * now[c] / before : 0.0;
            // Opened: the pressure escapes through the opening, over a few frames.
            if (policy == VolumePolicy::burst && !v.cap_loops.empty()) v.leak = std::max(v.leak, leak);
        }
        if (v.rest_volume > 0.0 && (unchanged || holds_air(v, now[c], b.particles.x))) {
            rebuilt.push_back(uint32_t(out.size()));
            out.push_back(std::move(v));
        }
    }
    b.volumes = std::move(out);
    return nc;
}

} // namespace pbdsplat::topology
