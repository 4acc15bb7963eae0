#include "pbdsplat/splat_sphere.h"

#include <cmath>

#include "core/timer.h"
#include "mesh/procedural.h"
#include "mesh/topology.h"
#include "passes/mesh_image.h"

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

core::Result<MeshRasterFigures> bench_mesh_raster(gpu::Context& ctx, uint32_t count, const render::FrameInputs& frame,
                                                  uint32_t width, uint32_t height, uint32_t warmup, uint32_t repeat) {
    // Level L has 10 * 4^L + 2 vertices; take the level nearest to `count` in ratio.
    uint32_t level = 0;
    while (level < 8 && std::abs(std::log(double(10u << (2 * (level + 1))) / count)) < std::abs(std::log(double(10u << (2 * level)) / count)))
        ++level;
    const mesh::TriangleMesh sphere = mesh::icosphere(level, 1.0f);
    std::vector<Vec4f> x;
    std::vector<Vec3f> normals;
    for (const Vec3f& p : sphere.positions) {
        x.emplace_back(p.x(), p.y(), p.z(), 1.0f);
        normals.push_back(p.normalized());
    }
    render::MeshRasterOptions o;
    o.width = width;
    o.height = height;
    o.max_vertices = x.size();
    o.max_triangles = sphere.triangles.size();
    auto raster = render::MeshRaster::create(ctx, o);
    if (!raster.ok()) return raster.error();
    PBDSPLAT_TRY(raster.value()->set_mesh(x, sphere.triangles, normals));
    std::vector<double> ms;
    for (uint32_t i = 0; i < warmup + repeat; ++i) {
        auto img = passes::render_mesh_image(ctx, *raster.value(), frame, render::MeshView::shaded);
        if (!img.ok()) return img.error();
        if (i >= warmup) ms.push_back(img->gpu_ms);
    }
    return MeshRasterFigures{x.size(), sphere.triangles.size(), core::median(ms)};
}

} // namespace pbdsplat::cli
