#include "sim/shape.h"

#include <algorithm>
#include <cmath>

#include "mesh/topology.h"

namespace pbdsplat::sim {

namespace {

// The welds' components joined: each component's cluster, numbered from 0 in order.
uint32_t join_welded(std::vector<uint32_t>& comp_of_vertex, uint32_t components, std::span<const std::pair<uint32_t, uint32_t>> welds) {
    std::vector<uint32_t> root(components);
    for (uint32_t c = 0; c < components; ++c) root[c] = c;
    const auto find = [&](uint32_t c) {
        while (root[c] != c) c = root[c] = root[root[c]];
        return c;
    };
    for (const auto& [i, j] : welds) {
        if (i >= comp_of_vertex.size() || j >= comp_of_vertex.size()) continue;
        const uint32_t a = comp_of_vertex[i], b = comp_of_vertex[j];
        if (a == UINT32_MAX || b == UINT32_MAX) continue;
        const uint32_t ra = find(a), rb = find(b);
        if (ra != rb) root[std::max(ra, rb)] = std::min(ra, rb);
    }
    std::vector<uint32_t> number(components, UINT32_MAX);
    uint32_t clusters = 0;
    for (uint32_t c = 0; c < components; ++c)
        if (find(c) == c) number[c] = clusters++;
    for (uint32_t& c : comp_of_vertex)
        if (c != UINT32_MAX) c = number[find(c)];
    return clusters;
}

} // namespace

float stiffest_shape(std::span<const ShapeCluster> clusters, float settings) {
    float most = 0.0f;
    for (const ShapeCluster& c : clusters) most = std::max(most, stiffness_of(c, settings));
    return most;
}

float softest_shape(std::span<const ShapeCluster> clusters, float settings) {
    if (clusters.empty()) return 0.0f;
    float least = 1.0f;
    for (const ShapeCluster& c : clusters) least = std::min(least, stiffness_of(c, settings));
    return least;
}

std::vector<ShapeCluster> build_shape_clusters(std::span<const mesh::Triangle> triangles, std::span<const Vec3f> rest,
                                               std::span<const float> w, std::span<const std::pair<uint32_t, uint32_t>> welds) {
    std::vector<uint32_t> comp;
    uint32_t n = mesh::vertex_components(triangles, rest.size(), comp);
    std::vector<uint32_t> comp_of_vertex(rest.size(), UINT32_MAX);
    for (size_t t = 0; t < triangles.size(); ++t)
        for (uint32_t v : triangles[t]) comp_of_vertex[v] = comp[t];
    if (!welds.empty()) n = join_welded(comp_of_vertex, n, welds);
    std::vector<ShapeCluster> out(n);
    float heaviest = 0.0f;
    for (float wi : w)
        if (wi > 0.0f) heaviest = std::max(heaviest, 1.0f / wi);
    for (uint32_t v = 0; v < rest.size(); ++v) {
        if (comp_of_vertex[v] == UINT32_MAX) continue;
        ShapeCluster& c = out[comp_of_vertex[v]];
        c.particles.push_back(v);
        // A pinned particle anchors the fit: much heavier than any free one.
        c.mass.push_back(w[v] > 0.0f ? 1.0f / w[v] : 100.0f * std::max(heaviest, 1e-12f));
    }
    for (ShapeCluster& c : out) {
        double total = 0.0;
        Vec3d centre = Vec3d::Zero();
        for (size_t k = 0; k < c.particles.size(); ++k) centre += double(c.mass[k]) * rest[c.particles[k]].cast<double>(), total += c.mass[k];
        centre /= std::max(total, 1e-30);
        c.rest.resize(c.particles.size());
        for (size_t k = 0; k < c.particles.size(); ++k) c.rest[k] = (rest[c.particles[k]].cast<double>() - centre).cast<float>();
    }
    std::erase_if(out, [](const ShapeCluster& c) { return c.particles.size() < 3; });
    return out;
}

namespace {
// The rotation of the polar decomposition of A, by Mueller et al. 2016 ("A robust method to
// extract the rotational part of deformations"): warm-started, never flips to a reflection.
void extract_rotation(const Mat3f& a, Eigen::Quaternionf& q, int iterations) {
    for (int it = 0; it < iterations; ++it) {
        const Mat3f r = q.matrix();
        const Vec3f omega = r.col(0).cross(a.col(0)) + r.col(1).cross(a.col(1)) + r.col(2).cross(a.col(2));
        const float denom = std::abs(r.col(0).dot(a.col(0)) + r.col(1).dot(a.col(1)) + r.col(2).dot(a.col(2))) + 1e-9f;
        const Vec3f step = omega / denom;
        const float angle = step.norm();
        if (!(angle > 1e-7f) || !std::isfinite(angle)) break;
        q = Eigen::Quaternionf(Eigen::AngleAxisf(angle, step / angle)) * q;
        q.normalize();
    }
}
} // namespace

template <class Real>
void project_shape(ShapeCluster& c, ParticlesT<Real>& p, Real stiffness, bool xpbd, Real alpha_tilde) {
    const size_t n = c.particles.size();
    if (n == 0) return;
    // Centre of mass and the covariance of current positions against rest offsets.
    Vec3d centre = Vec3d::Zero();
    double total = 0.0;
    for (size_t k = 0; k < n; ++k) {
        centre += double(c.mass[k]) * p.x[c.particles[k]].template head<3>().template cast<double>();
        total += c.mass[k];
    }
    centre /= total;
    const Vec3f cf = centre.cast<float>();
    Mat3f a = Mat3f::Zero();
    for (size_t k = 0; k < n; ++k) {
        const Vec3f d = p.x[c.particles[k]].template head<3>().template cast<float>() - cf;
        a.noalias() += c.mass[k] * d * c.rest[k].transpose();
    }
    if (!a.allFinite()) return;
    if (c.fresh) {
        // From scratch (new body, new piece after a cut): an SVD gives the right basin.
        Eigen::JacobiSVD<Mat3f> svd(a, Eigen::ComputeFullU | Eigen::ComputeFullV);
        Mat3f r = svd.matrixU() * svd.matrixV().transpose();
        if (r.determinant() < 0.0f) {
            Mat3f u = svd.matrixU();
            u.col(2) *= -1.0f;
            r = u * svd.matrixV().transpose();
        }
        c.rotation = Eigen::Quaternionf(r).normalized();
        c.fresh = false;
    }
    extract_rotation(a, c.rotation, 4);
    const Mat3f r = c.rotation.matrix();
    for (size_t k = 0; k < n; ++k) {
        const uint32_t i = c.particles[k];
        const Real wi = p.w[i];
        if (wi == Real(0)) continue;
        const Vec3f goal = r * c.rest[k] + cf;
        const Real s = xpbd ? wi / (wi + alpha_tilde) : stiffness;
        const Vec4<Real> g(Real(goal.x()), Real(goal.y()), Real(goal.z()), Real(0));
        p.x[i] += s * (g - p.x[i]);
    }
}

template void project_shape<float>(ShapeCluster&, ParticlesT<float>&, float, bool, float);
template void project_shape<double>(ShapeCluster&, ParticlesT<double>&, double, bool, double);

} // namespace pbdsplat::sim
