#pragma once
// A minimal hand-written PBD loop of Stage A's workload (gravity and damping, I iterations of
// distance constraints in edge order and one global volume constraint, velocity update, vertex
// normals; one thread, PBD), the yardstick `bench sim --baseline` measures the engine against in
// the same run. Written as plainly as a careful engineer would without the engine's structure
// (no colouring, no stage functions, scatter instead of gathers): what the engine's layout must
// at least match.
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
    };
    // `pinned`: a particle that does not move (or UINT32_MAX). Masses by lumped area, as the engine's.
    SimBaseline(const mesh::TriangleMesh& mesh, uint32_t pinned, const Settings& settings);
    void step(float dt);
    const std::vector<Vec4f>& positions() const { return x_; }

private:
    struct Edge {
        uint32_t i, j;
        float rest;
    };
    Settings s_;
    std::vector<Vec4f> x_, p_, v_, grad_;
    std::vector<Vec3f> n_;
    std::vector<float> w_;
    std::vector<Edge> edges_;
    std::vector<mesh::Triangle> triangles_;
    double rest_volume_ = 0.0;
};

} // namespace pbdsplat::cli
