#include <doctest/doctest.h>

#include "gpu/device.h"
#include "render/splat_pass.h"

using namespace pbdsplat;

// Which path `auto` takes follows the measured figures in docs/BENCHMARKS.md ("The renderer"):
// a change of the rule must come with new figures.
TEST_SUITE("render/splat_path") {
    TEST_CASE("auto takes the geometry shader on a CPU device, vertex pulling for a GPU's captures, its mesh shader for the rest") {
        gpu::DeviceCaps lavapipe;
        lavapipe.type = "cpu";
        lavapipe.geometry_shader = lavapipe.mesh_shader = true;
        CHECK(render::best_splat_path(lavapipe) == render::SplatPath::geometry);
        CHECK(render::best_splat_path(lavapipe, true) == render::SplatPath::geometry);

        gpu::DeviceCaps gpu = lavapipe;
        gpu.type = "discrete";
        CHECK(render::best_splat_path(gpu) == render::SplatPath::mesh);
        CHECK(render::best_splat_path(gpu, true) == render::SplatPath::vertex);
        gpu.mesh_shader = false;
        CHECK(render::best_splat_path(gpu) == render::SplatPath::geometry);
        gpu.geometry_shader = false;
        CHECK(render::best_splat_path(gpu) == render::SplatPath::vertex);
    }
}
