#include "scene/coverage.h"

#include "scene/mesh_image.h"
#include "scene/offscreen_renderer.h"

namespace pbdsplat::scene {
namespace {

core::Result<core::ImageRgba8> mesh_mask(gpu::Context& ctx, std::span<const Vec4f> x,
                                         std::span<const std::array<uint32_t, 3>> triangles,
                                         const render::FrameInputs& frame, uint32_t width, uint32_t height) {
    render::MeshRasterOptions mo;
    mo.width = width;
    mo.height = height;
    mo.max_vertices = x.size();
    mo.max_triangles = triangles.size();
    auto raster = render::MeshRaster::create(ctx, mo);
    if (!raster.ok()) return raster.error();
    PBDSPLAT_TRY(raster.value()->set_mesh(x, triangles));
    auto image = render_mesh_image(ctx, *raster.value(), frame, render::MeshView::mask);
    if (!image.ok()) return image.error();
    return std::move(image->image);
}

} // namespace

core::Result<Coverage> measure_coverage(gpu::Context& ctx, std::span<const Vec4f> x,
                                        std::span<const std::array<uint32_t, 3>> triangles,
                                        std::span<const splat::GaussianRecord> records, render::FrameInputs frame,
                                        uint32_t width, uint32_t height) {
    Coverage c;
    auto mesh = mesh_mask(ctx, x, triangles, frame, width, height);
    if (!mesh.ok()) return mesh.error();
    c.mesh = std::move(mesh).value();

    render::RendererOptions ro;
    ro.width = width;
    ro.height = height;
    ro.max_splats = uint32_t(std::max<size_t>(1, records.size()));
    ro.frames_in_flight = 1;
    auto splats = OffscreenRenderer::create(ctx, ro);
    if (!splats.ok()) return splats.error();
    frame.background = Vec4f::Zero();  // the accumulated alpha is then the splats' coverage
    PBDSPLAT_TRY(splats.value()->render(records, frame));
    auto image = splats.value()->finish();
    if (!image.ok()) return image.error();
    c.splats = std::move(image).value();

    size_t holes = 0, both = 0, either = 0;
    for (size_t i = 0; i < size_t(width) * height; ++i) {
        const bool in_mesh = c.mesh.pixels[i * 4 + 3] >= 128;
        const bool in_splats = c.splats.pixels[i * 4 + 3] >= 128;
        c.mesh_pixels += in_mesh ? 1 : 0;
        holes += (in_mesh && !in_splats) ? 1 : 0;
        both += (in_mesh && in_splats) ? 1 : 0;
        either += (in_mesh || in_splats) ? 1 : 0;
    }
    if (c.mesh_pixels == 0) return core::make_error("the mesh is not in view: no coverage to measure");
    c.hole_ratio = double(holes) / double(c.mesh_pixels);
    c.silhouette_iou = double(both) / double(either);
    return c;
}

} // namespace pbdsplat::scene
