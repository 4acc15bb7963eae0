#include "sim/pose.h"

#include <algorithm>
#include <cmath>

#include "core/math.h"

namespace pbdsplat::sim {

namespace {
struct ModelSums {
    size_t count = 0;
    Vec3d rest_centre = Vec3d::Zero(), centre = Vec3d::Zero();
    double rest_low = INFINITY, rest_high = -INFINITY, low = INFINITY, high = -INFINITY;
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
};

// The rotation that best maps rest offsets onto current ones (Kabsch), never a reflection.
Eigen::Matrix3d best_rotation(const Eigen::Matrix3d& h) {
    Eigen::JacobiSVD<Eigen::Matrix3d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
    d(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
    return svd.matrixU() * d * svd.matrixV().transpose();
}
} // namespace

PoseReport pose_report(const SoftBody& body) {
    const size_t n = body.particle_count();
    auto model = [&](size_t i) { return i < body.model_of_particle.size() ? body.model_of_particle[i] : 0u; };
    uint32_t models = 0;
    for (size_t i = 0; i < n; ++i) models = std::max(models, model(i) + 1);
    std::vector<ModelSums> m(models);
    // Particles in no triangle (none yet, or left by an edit) are not part of what a user sees.
    std::vector<char> used(n, 0);
    for (const mesh::Triangle& t : body.triangles)
        for (uint32_t v : t) used[v] = 1;
    for (size_t i = 0; i < n; ++i) {
        if (!used[i]) continue;
        ModelSums& s = m[model(i)];
        const Vec3d r = body.rest_positions[i].cast<double>(), x = body.particles.x[i].head<3>().cast<double>();
        ++s.count, s.rest_centre += r, s.centre += x;
        s.rest_low = std::min(s.rest_low, r.y()), s.rest_high = std::max(s.rest_high, r.y());
        s.low = std::min(s.low, x.y()), s.high = std::max(s.high, x.y());
    }
    for (ModelSums& s : m)
        if (s.count) s.rest_centre /= double(s.count), s.centre /= double(s.count);
    for (size_t i = 0; i < n; ++i) {
        if (!used[i]) continue;
        ModelSums& s = m[model(i)];
        s.covariance += (body.particles.x[i].head<3>().cast<double>() - s.centre) * (body.rest_positions[i].cast<double>() - s.rest_centre).transpose();
    }
    PoseReport out;
    for (const ModelSums& s : m) {
        if (s.count < 3) continue;
        const Vec3d up = best_rotation(s.covariance) * Vec3d::UnitY();
        out.tilt_max_degrees = std::max(out.tilt_max_degrees, std::acos(std::clamp(up.y(), -1.0, 1.0)) * 180.0 / double(k_pi));
        if (s.rest_high > s.rest_low) out.height_ratio_min = std::min(out.height_ratio_min, (s.high - s.low) / (s.rest_high - s.rest_low));
    }
    return out;
}

size_t smallest_piece_triangles(const SoftBody& body) {
    size_t smallest = 0;
    for (size_t c : piece_triangle_counts(body.triangles, body.piece_of_particle, body.pieces))
        if (c > 0 && (smallest == 0 || c < smallest)) smallest = c;
    return smallest;
}

} // namespace pbdsplat::sim
