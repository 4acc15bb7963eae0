#include "scene/builtin_scene.h"

#include "mesh/procedural.h"

namespace pbdsplat::scene {

BuiltinScene make_builtin_scene(uint32_t level) {
    BuiltinScene s;
    s.mesh = mesh::icosphere(level, 1.0f);
    // A splat's standard deviation of about 0.6 edge lengths closes the surface between vertices
    // without blurring the silhouette (3 sigma reaches past the neighbours).
    s.appearance.scale = 0.6f * mesh::mean_edge_length(s.mesh);
    s.appearance.albedo = Vec3f(0.85f, 0.32f, 0.25f);
    s.appearance.opacity_logit = 4.0f;
    s.frame.camera.eye = Vec3f(0.0f, 0.6f, 3.2f);
    s.frame.camera.target = Vec3f::Zero();
    const auto normals = mesh::vertex_normals(s.mesh);
    splat::map_points(s.mesh.positions, normals, s.appearance, s.records);
    return s;
}

} // namespace pbdsplat::scene
