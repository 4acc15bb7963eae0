#pragma once
// One deformable body: its particles, its surface triangles and its constraints, built from a
// repaired mesh. The solver stages operate on it; the topology stage (cuts) is the only other
// code that changes it.
#include <string>
#include <vector>

#include "core/result.h"
#include "mesh/triangle_mesh.h"
#include "sim/constraints.h"
#include "sim/particles.h"

namespace pbdsplat::sim {

enum class MassMode { area, uniform };

struct SoftBodyDesc {
    float total_mass = 1.0f;      // kg, spread over the particles
    MassMode mass_mode = MassMode::area;
    float stretch_compliance = 0.0f;  // per distance constraint (XPBD)
    bool volume = true;            // one volume constraint per component
    float pressure = 1.0f;         // k of every volume constraint
    float volume_compliance = 0.0f;
    bool reorder = true;           // Morton-order particles for cache locality
};

struct SoftBody {
    Particles particles;
    std::vector<Vec3f> normals;  // per particle, updated each step
    std::vector<mesh::Triangle> triangles;
    std::vector<DistanceConstraint> distance;
    std::vector<float> distance_lambda;  // XPBD multipliers, one per distance constraint
    std::vector<VolumeConstraint> volumes;
    std::vector<Vec3f> rest_positions;  // rest state (new edges take rest lengths from it)

    size_t particle_count() const { return particles.size(); }
    // Current volume of each volume constraint (caps included).
    double volume(size_t constraint) const;
    // Pins the particle (inverse mass 0); it then moves only if the scene moves it.
    void pin(uint32_t particle) { particles.w[particle] = 0.0f; }
    // The particle with the largest `axis` coordinate (ties: lowest index).
    uint32_t extreme_particle(int axis, bool largest = true) const;
};

// Builds the body. `mesh` must be repaired (manifold with boundary, outward); the mesh's vertex
// order may change (reorder), so the body's particles are the reference afterwards.
core::Result<SoftBody> make_soft_body(mesh::TriangleMesh mesh, const SoftBodyDesc& desc);

} // namespace pbdsplat::sim
