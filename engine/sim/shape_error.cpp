#include "sim/shape_error.h"

#include <algorithm>
#include <cmath>

#include "core/assert.h"

namespace pbdsplat::sim {

ShapeReport shape_report(const SoftBody& body, size_t min_particles) {
    ShapeReport out;
    const size_t n = body.particle_count();
    // The body's own piece labels (kept by topology edits): pieces[c] is piece c's, and none is
    // empty, since every piece has a triangle.
    const std::vector<uint32_t>& comp = body.piece_of_particle;
    PBDSPLAT_ASSERT(comp.size() == n, "shape_report: the piece labels do not cover the particles; call rebuild_derived(body)");
    std::vector<std::vector<uint32_t>> members(body.pieces);
    for (uint32_t v = 0; v < n; ++v)
        if (comp[v] != k_no_piece) members[comp[v]].push_back(v);
    for (const auto& m : members) {
        Vec3d rc = Vec3d::Zero(), xc = Vec3d::Zero();
        Eigen::AlignedBox3d box;
        for (uint32_t v : m) {
            const Vec3d r = body.rest_positions[v].cast<double>();
            rc += r, xc += body.particles.x[v].head<3>().cast<double>();
            box.extend(r);
        }
        rc /= double(m.size()), xc /= double(m.size());
        Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
        for (uint32_t v : m)
            h += (body.particles.x[v].head<3>().cast<double>() - xc) * (body.rest_positions[v].cast<double>() - rc).transpose();
        Eigen::JacobiSVD<Eigen::Matrix3d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
        Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
        d(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
        const Eigen::Matrix3d r = svd.matrixU() * d * svd.matrixV().transpose();
        double sum = 0.0;
        for (uint32_t v : m) {
            const Vec3d aligned = r * (body.rest_positions[v].cast<double>() - rc) + xc;
            sum += (body.particles.x[v].head<3>().cast<double>() - aligned).squaredNorm();
        }
        const double diag = std::max(box.diagonal().norm(), 1e-12);
        out.pieces.push_back({m.size(), std::sqrt(sum / double(m.size())) / diag, 0.0});
    }
    // The volume constraint of each piece, by its label.
    for (size_t k = 0; k < body.volumes.size(); ++k) {
        const VolumeConstraint& vc = body.volumes[k];
        if (vc.triangle_count == 0 || !(vc.rest_volume > 0.0) || vc.leak > 0.0f) continue;  // opened: no volume to keep
        const double err = std::abs(body.volume(k) / (vc.rest_volume * double(vc.pressure)) - 1.0);
        PieceShape& piece = out.pieces[vc.piece];
        piece.volume_error = std::max(piece.volume_error, err);
    }
    std::stable_sort(out.pieces.begin(), out.pieces.end(), [](const PieceShape& a, const PieceShape& b) { return a.particles > b.particles; });
    for (const PieceShape& p : out.pieces)
        if (p.particles >= min_particles) out.max_error = std::max(out.max_error, p.error);
    return out;
}

double edge_stretch_max(const SoftBody& body) {
    double rest_sum = 0.0;
    size_t live = 0;
    for (const DistanceConstraint& c : body.distance)
        if (c.alive()) rest_sum += double(c.rest), ++live;
    if (live == 0 || !(rest_sum > 0.0)) return 0.0;
    // A sliver's edge, a hundredth of the mean, grown to a mean edge is no spike.
    const double mean_rest = rest_sum / double(live);
    double most = 0.0;
    for (const DistanceConstraint& c : body.distance) {
        if (!c.alive()) continue;
        const double length = double((xyz(body.particles.x[c.i]) - xyz(body.particles.x[c.j])).norm());
        most = std::max(most, length / std::max(double(c.rest), mean_rest));
    }
    return most;
}

} // namespace pbdsplat::sim
