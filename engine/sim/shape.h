#pragma once
// Shape matching (Mueller et al. 2005): each connected piece of the body is pulled toward its
// rest shape, rotated and moved to fit the current positions best (least squares). A closed
// shell held only by edge lengths and a global volume has no resistance to bending: it sags
// into a puddle under gravity. One cluster per piece keeps a resting bunny a bunny at any
// resolution and any iteration count, costs two passes over the particles per iteration, and
// follows cuts for free: a cut makes new pieces, each gets its own cluster from its own rest
// positions. Balloons that must wrinkle and deflate leave it off (stiffness 0).
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "core/math.h"
#include "mesh/triangle_mesh.h"
#include "sim/particles.h"

namespace pbdsplat::sim {

struct ShapeCluster {
    std::vector<uint32_t> particles;
    std::vector<Vec3f> rest;  // rest position minus the rest centre of mass, per particle
    std::vector<float> mass;  // weights of the fit: 1/w, pinned particles heavy
    Eigen::Quaternionf rotation = Eigen::Quaternionf::Identity();  // the last fit's: warm start
    bool fresh = true;  // no fit yet: the first one starts from a full polar decomposition
    // Its body's own shape stiffness (a scene's per-body `shape_stiffness`: a soft cushion under
    // a stiff ball); negative: the solver settings'.
    float own_stiffness = -1.0f;
};

inline float stiffness_of(const ShapeCluster& c, float settings) { return c.own_stiffness >= 0.0f ? c.own_stiffness : settings; }
// The stiffest cluster's: whether anything keeps a shape, or answers contact as a solid; and the
// softest's (0 for none): whether any skin may fold.
float stiffest_shape(std::span<const ShapeCluster> clusters, float settings);
float softest_shape(std::span<const ShapeCluster> clusters, float settings);

// One cluster per connected component of `triangles` (through shared vertices), components
// joined by a weld (a pair of particles: a teapot's spout, handle and lid held to its body) in
// one cluster: a model of welded parts keeps its shape as the one object it is, where a cluster
// per part let a spout swing down at its weld ring like a hinge.
std::vector<ShapeCluster> build_shape_clusters(std::span<const mesh::Triangle> triangles, std::span<const Vec3f> rest,
                                               std::span<const float> inverse_mass,
                                               std::span<const std::pair<uint32_t, uint32_t>> welds = {});

// PBD: every free particle moves `stiffness` of the way to its goal (rotated rest + centre).
// XPBD (`alpha_tilde` = compliance / dt^2 >= 0): the step is w / (w + alpha_tilde) of the gap.
template <class Real>
void project_shape(ShapeCluster& cluster, ParticlesT<Real>& p, Real stiffness, bool xpbd, Real alpha_tilde);

} // namespace pbdsplat::sim
