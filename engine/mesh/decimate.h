#pragma once
// The simulation mesh of a detailed model: quadric edge-collapse decimation (meshoptimizer's
// meshopt_simplify) to a target vertex count, then the usual repair. The physics runs on this
// coarse mesh; the model's full-resolution surface rides on it as embedded samples
// (surface/embedding.h), so detail and density do not cost solver time.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/result.h"
#include "mesh/repair.h"

namespace pbdsplat::mesh {

struct DecimateOptions {
    uint32_t target_vertices = 2000;  // the simplifier stops near this (or earlier, see below)
    // Open boundaries (the teapot's rim, a scan's holes) stay where they are: collapsing them
    // would shrink the openings the model has.
    bool lock_border = true;
};

struct DecimateReport {
    size_t input_vertices = 0, input_triangles = 0;
    size_t output_vertices = 0, output_triangles = 0;
    // meshoptimizer's own error estimate, as a share of the mesh's extent.
    float relative_error = 0.0f;
    RepairReport repair;  // of the decimated mesh
};

struct DecimatedMesh {
    TriangleMesh mesh;
    DecimateReport report;
};

// Decimates a repaired mesh. A target at or above the mesh's vertex count returns the mesh
// as it is. The result keeps only vertices of the input (no new positions), so at rest every
// simulation particle lies on the fine surface. `name` goes into error messages.
core::Result<DecimatedMesh> decimate(const TriangleMesh& mesh, const DecimateOptions& options, const std::string& name);

// A surface to draw rather than to simulate: `triangles` over `positions` simplified as far as
// they stay within `max_error` (world units, meshoptimizer's quadric estimate: a vertex of a
// simplified dome lay 1.66x it away) of it, as triangles over the same vertices (no
// vertex moves or is renumbered), borders where they are. What the mesh occluders draw of a
// detailed model (render/occluder_pass.h), whose full triangle count bought nothing within
// their tolerance. The triangles as they are when there is nothing to simplify.
std::vector<Triangle> simplify_triangles(std::span<const Vec3f> positions, std::span<const Triangle> triangles, float max_error);

} // namespace pbdsplat::mesh
