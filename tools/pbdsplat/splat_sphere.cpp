#include "pbdsplat/splat_sphere.h"

#include <cmath>

#include "mesh/procedural.h"

namespace pbdsplat::cli {

SplatSphere make_splat_sphere(uint32_t count) {
    SplatSphere s;
    const auto points = mesh::fibonacci_sphere(count, 1.0f);
    splat::Appearance look;
    look.scale = 0.6f * std::sqrt(4.0f * k_pi / float(count));  // about 0.6 of the mean spacing
    splat::map_points(points, points, look, s.records);
    s.frame.camera.eye = Vec3f(0.0f, 0.5f, 3.5f);
    return s;
}

} // namespace pbdsplat::cli
