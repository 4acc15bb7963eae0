#pragma once
// A minimal hand-written PBD loop of Stage A's workload (gravity and damping, I iterations of
// distance constraints in edge order and one global volume constraint, velocity update, vertex
// normals; one thread, PBD), the yardstick `bench sim --baseline` measures the engine against in
// the same run. Written as plainly as a careful engineer would without the engine's structure
// (no colouring, no stage functions, scatter instead of gathers): what the engine's layout must
// at least match.
//
// With `tuned`, the same Gauss-Seidel loop as a performance-minded engineer would hand-write it,
// still without the engine's structure: the edges ordered so that none shares a particle with
// the three before it (each projection then need not wait for the previous one's store), each
// edge carrying its two mass shares (no weight loads or division per projection), constrained
// pairs of two pinned particles dropped at build time; the volume gradient gathered per particle
// from its ring of triangles (each particle's sum stays in registers instead of three scattered
// read-modify-writes per triangle), and so are the vertex normals, with a cross product kept in
// registers (sim/vec4_ops.h). The outside reference was such a
// loop; this one stands for it in the same run.
#include <cstdint>
#include <vector>

#include "core/math.h"
#include "mesh/triangle_mesh.h"

namespace pbdsplat::cli {

class SimBaseline {
public:
    struct Settings {
        Vec3f gravity{0.0f, -9.81f, 0.0f};
        float damping = 0.0f;            // 1/s
        float stretch_stiffness = 1.0f;  // per frame's worth of iterations
        float volume_stiffness = 1.0f;
        uint32_t iterations = 5;
        bool volume = true;
        bool tuned = false;
    };
    // `pinned`: a particle that does not move (or UINT32_MAX). Masses by lumped area, as the engine's.
    SimBaseline(const mesh::TriangleMesh& mesh, uint32_t pinned, const Settings& settings);
    void step(float dt);
    const std::vector<Vec4f>& positions() const { return x_; }

private:
    struct Edge {
        uint32_t i, j;
        float rest;
        float share_i = 0.0f, share_j = 0.0f;  // w_i / (w_i + w_j), w_j / (w_i + w_j): tuned only
    };
    void prepare_tuned();  // the tuned loop's edge order, mass shares and rings
    void project_edges_plain(float ks);
    void project_edges_tuned(float ks);
    void project_volume_plain(float kv);
    void project_volume_tuned(float kv);
    void update_normals_plain();
    void update_normals_tuned();
    Settings s_;
    std::vector<Vec4f> x_, p_, v_, grad_;
    std::vector<Vec3f> n_;
    std::vector<float> w_;
    std::vector<Edge> edges_;
    std::vector<mesh::Triangle> triangles_;
    // Tuned: particle i's triangles as the other two corners in winding order, (b, c) at
    // ring_[ring_start_[i]] .. ring_[ring_start_[i + 1]] - 1, so the gradient is the sum of b x c.
    std::vector<uint32_t> ring_start_;
    std::vector<std::pair<uint32_t, uint32_t>> ring_;
    double rest_volume_ = 0.0;
};

} // namespace pbdsplat::cli
