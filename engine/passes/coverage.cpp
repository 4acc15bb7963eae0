#include "passes/coverage.h"

#include <cmath>
#include <memory>
#include <vector>

#include "passes/mesh_image.h"
#include "passes/offscreen_renderer.h"

namespace pbdsplat::passes {
namespace {

// Area-weighted vertex normals of the deformed mesh, for the lit image.
std::vector<Vec3f> vertex_normals(std::span<const Vec4f> x, std::span<const std::array<uint32_t, 3>> triangles) {
    std::vector<Vec3f> normals(x.size(), Vec3f::Zero());
    for (const auto& t : triangles) {
        const Vec3f n = (x[t[1]] - x[t[0]]).head<3>().cross((x[t[2]] - x[t[0]]).head<3>());
        for (uint32_t v : t) normals[v] += n;
    }
    for (Vec3f& n : normals) n = n.norm() > 0.0f ? Vec3f(n.normalized()) : Vec3f::UnitZ();
    return normals;
}

// A textured mesh on corners of its own (a vertex has a texture coordinate per triangle where a
// seam runs through it), lit with the shared vertices' normals.
core::Status set_textured_mesh(render::MeshRaster& raster, std::span<const Vec4f> x, std::span<const std::array<uint32_t, 3>> triangles,
                               const ReferenceTextures& textures) {
    const std::vector<Vec3f> shared = vertex_normals(x, triangles);
    const size_t n = triangles.size() * 3;
    std::vector<Vec4f> corners(n);
    std::vector<Vec3f> normals(n), colors(n);
    std::vector<Vec2f> uv(n);
    std::vector<std::array<uint32_t, 3>> split(triangles.size());
    for (size_t t = 0; t < triangles.size(); ++t)
        for (size_t k = 0; k < 3; ++k) {
            const size_t c = t * 3 + k;
            corners[c] = x[triangles[t][k]];
            normals[c] = shared[triangles[t][k]];
            colors[c] = textures.tint[t][k];
            uv[c] = textures.uv[t][k];
            split[t][k] = uint32_t(c);
        }
    PBDSPLAT_TRY(raster.set_textures(textures.textures));
    const render::MeshTexturing texturing{uv, textures.triangle_texture};
    return raster.set_mesh(corners, split, normals, 0, colors, &texturing);
}

core::Result<std::unique_ptr<render::MeshRaster>> mesh_raster(gpu::Context& ctx, std::span<const Vec4f> x,
                                                              std::span<const std::array<uint32_t, 3>> triangles,
                                                              uint32_t width, uint32_t height, std::span<const Vec3f> colors) {
    render::MeshRasterOptions mo;
    mo.width = width;
    mo.height = height;
    mo.max_vertices = x.size();
    mo.max_triangles = triangles.size();
    auto raster = render::MeshRaster::create(ctx, mo);
    if (!raster.ok()) return raster.error();
    PBDSPLAT_TRY(raster.value()->set_mesh(x, triangles, vertex_normals(x, triangles), 0, colors));
    return std::move(raster).value();
}

// The mean of each k x k block of `fine`, in the image's own (display) encoding, as the splats
// blend.
core::ImageRgba8 box_down(const core::ImageRgba8& fine, uint32_t k) {
    core::ImageRgba8 out;
    out.width = fine.width / k;
    out.height = fine.height / k;
    out.pixels.resize(size_t(out.width) * out.height * 4);
    for (uint32_t y = 0; y < out.height; ++y)
        for (uint32_t x = 0; x < out.width; ++x)
            for (uint32_t c = 0; c < 4; ++c) {
                uint32_t sum = 0;
                for (uint32_t dy = 0; dy < k; ++dy)
                    for (uint32_t dx = 0; dx < k; ++dx)
                        sum += fine.pixels[((size_t(y) * k + dy) * fine.width + size_t(x) * k + dx) * 4 + c];
                out.pixels[(size_t(y) * out.width + x) * 4 + c] = uint8_t((sum + k * k / 2) / (k * k));
            }
    return out;
}

// The lit textured mesh, each pixel the mean of 4 x 4 samples: a texture's edges fall inside
// pixels, and a pixel's colour is then the mean over its area, as the splats (themselves soft)
// draw it, not whichever side its centre happens to fall on.
core::Result<core::ImageRgba8> textured_image(gpu::Context& ctx, std::span<const Vec4f> x, std::span<const std::array<uint32_t, 3>> triangles,
                                              const ReferenceTextures& textures, const render::FrameInputs& frame, uint32_t width,
                                              uint32_t height) {
    if (textures.triangle_texture.size() != triangles.size() || textures.uv.size() != triangles.size() ||
        textures.tint.size() != triangles.size())
        return core::make_error("measure_coverage: the textured look needs one entry per triangle");
    constexpr uint32_t k_samples = 4;
    render::MeshRasterOptions mo;
    mo.width = width * k_samples;
    mo.height = height * k_samples;
    mo.max_vertices = triangles.size() * 3;
    mo.max_triangles = triangles.size();
    auto raster = render::MeshRaster::create(ctx, mo);
    if (!raster.ok()) return raster.error();
    PBDSPLAT_TRY(set_textured_mesh(*raster.value(), x, triangles, textures));
    auto image = render_mesh_image(ctx, *raster.value(), frame, render::MeshView::shaded, Vec3f::Ones());
    if (!image.ok()) return image.error();
    return box_down(image->image, k_samples);
}

// The lit mesh in `albedo` times its vertex colours.
core::Result<core::ImageRgba8> lit_image(gpu::Context& ctx, render::MeshRaster& raster, const render::FrameInputs& frame,
                                         const Vec3f& albedo) {
    auto image = render_mesh_image(ctx, raster, frame, render::MeshView::shaded, albedo);
    if (!image.ok()) return image.error();
    return std::move(image->image);
}

} // namespace

double pixel_luminance(const uint8_t* p) { return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]; }

double speck_ratio(const core::ImageRgba8& splats, const core::ImageRgba8& shaded, const core::ImageRgba8& mask,
                   core::ImageRgba8* marked) {
    size_t inside = 0, specks = 0;
    if (marked) *marked = splats;
    for (size_t i = 0; i < size_t(mask.width) * mask.height; ++i) {
        // The inside of the surface, seen through an opening: the splats shade one side only.
        if (mask.pixels[i * 4 + 3] < 128 || mask.pixels[i * 4] < 128) continue;
        ++inside;
        const bool speck = pixel_luminance(&splats.pixels[i * 4]) < 0.5 * pixel_luminance(&shaded.pixels[i * 4]);
        specks += speck ? 1 : 0;
        if (speck && marked) {
            uint8_t* p = &marked->pixels[i * 4];
            p[0] = 255, p[1] = 0, p[2] = 255, p[3] = 255;
        }
    }
    return inside ? double(specks) / double(inside) : 0.0;
}

namespace {
// The mean of error(i) over the pixels i where the mesh's outside is seen (as speck_ratio counts).
template <class PixelError>
double mean_over_front(const core::ImageRgba8& mask, const PixelError& error) {
    size_t inside = 0;
    double sum = 0.0;
    for (size_t i = 0; i < size_t(mask.width) * mask.height; ++i) {
        if (mask.pixels[i * 4 + 3] < 128 || mask.pixels[i * 4] < 128) continue;
        ++inside;
        sum += error(i);
    }
    return inside ? sum / double(inside) : 0.0;
}
} // namespace

double shading_error(const core::ImageRgba8& splats, const core::ImageRgba8& shaded, const core::ImageRgba8& mask) {
    return mean_over_front(mask, [&](size_t i) {
        return std::abs(pixel_luminance(&splats.pixels[i * 4]) - pixel_luminance(&shaded.pixels[i * 4])) / 255.0;
    });
}

double edge_excess(const core::ImageRgba8& splats, const core::ImageRgba8& shaded, const core::ImageRgba8& mask) {
    const int w = int(mask.width), h = int(mask.height);
    const auto front = [&](int x, int y) {
        const uint8_t* p = &mask.pixels[(size_t(y) * size_t(w) + size_t(x)) * 4];
        return p[3] >= 128 && p[0] >= 128;
    };
    // The splats' luma less the lit mesh's: smooth where they differ only in tone (another
    // environment lookup, a softer highlight), rough where the splats add structure.
    std::vector<double> diff(size_t(w) * size_t(h), 0.0);
    for (size_t i = 0; i < diff.size(); ++i) diff[i] = pixel_luminance(&splats.pixels[i * 4]) - pixel_luminance(&shaded.pixels[i * 4]);
    constexpr int k_radius = 2;       // a 5x5 neighbourhood
    constexpr double k_rough = 4.0;   // luma steps (of 255) off the neighbourhood's mean
    size_t inside = 0, rough = 0;
    for (int y = k_radius; y + k_radius < h; ++y)
        for (int x = k_radius; x + k_radius < w; ++x) {
            bool all_front = true;
            double sum = 0.0;
            for (int dy = -k_radius; dy <= k_radius && all_front; ++dy)
                for (int dx = -k_radius; dx <= k_radius; ++dx) {
                    if (!front(x + dx, y + dy)) {
                        all_front = false;
                        break;
                    }
                    sum += diff[size_t(y + dy) * size_t(w) + size_t(x + dx)];
                }
            if (!all_front) continue;  // the silhouette is the IoU's to judge
            const double mean = sum / double((2 * k_radius + 1) * (2 * k_radius + 1));
            ++inside;
            rough += std::abs(diff[size_t(y) * size_t(w) + size_t(x)] - mean) > k_rough ? 1 : 0;
        }
    return inside ? double(rough) / double(inside) : 0.0;
}

double color_error(const core::ImageRgba8& splats, const core::ImageRgba8& shaded, const core::ImageRgba8& mask) {
    return mean_over_front(mask, [&](size_t i) {
        int sum = 0;
        for (size_t k = 0; k < 3; ++k) sum += std::abs(int(splats.pixels[i * 4 + k]) - int(shaded.pixels[i * 4 + k]));
        return double(sum) / (3.0 * 255.0);
    });
}

namespace {

// The splats as the runtime draws them, over a transparent background (the accumulated alpha is
// then their coverage), the mesh as their occluders where the style has them.
core::Result<core::ImageRgba8> splat_image(gpu::Context& ctx, const OccluderInput& occluders, std::span<const splat::GaussianRecord> records,
                                           render::FrameInputs frame, uint32_t width, uint32_t height,
                                           std::span<const splat::GaussianShape> shapes, const SplatTexturing* texturing) {
    render::RendererOptions ro;
    ro.width = width;
    ro.height = height;
    ro.max_splats = uint32_t(std::max<size_t>(1, records.size()));
    ro.frames_in_flight = 1;
    ro.anisotropic = !shapes.empty();
    ro.normalised = frame.style.blend == render::Blend::normalised;
    ro.occluders = render::occluded_style(frame.style);
    ro.textures = texturing && !texturing->texcoords.empty() ? uint32_t(texturing->textures.size()) : 0u;
    auto splats = OffscreenRenderer::create(ctx, ro);
    if (!splats.ok()) return splats.error();
    splats.value()->set_occluders(occluders.positions, occluders.triangles, occluders.one_sided);
    if (ro.textures > 0) {
        splats.value()->set_texcoords(texturing->texcoords);
        PBDSPLAT_TRY(splats.value()->set_textures(texturing->textures));
    }
    frame.background = Vec4f::Zero();
    PBDSPLAT_TRY(splats.value()->render(records, frame, {}, shapes));
    return splats.value()->finish();
}

} // namespace

double thin_ratio(const core::ImageRgba8& splats, const core::ImageRgba8& mesh_mask) {
    // 230 of 255: the coverage a maximal sample set stretched by the density control's own
    // threshold (1.1) still reaches midway between three samples (0.98); the dim worms between
    // samples (a sphere stretched by 1.35 before its refill, or the normalised weights made
    // sharper on purpose) measured 0.52-0.9.
    constexpr uint8_t k_thin_below = 230;
    constexpr int k_inner = 2;  // the neighbourhood's half-width: the outline's fade is left out
    const int w = int(splats.width), h = int(splats.height);
    const auto in_mesh = [&](int x, int y) { return mesh_mask.pixels[(size_t(y) * size_t(w) + size_t(x)) * 4 + 3] >= 128; };
    size_t inner = 0, thin = 0;
    for (int y = k_inner; y < h - k_inner; ++y)
        for (int x = k_inner; x < w - k_inner; ++x) {
            if (!in_mesh(x, y) || !in_mesh(x - k_inner, y) || !in_mesh(x + k_inner, y) || !in_mesh(x, y - k_inner) || !in_mesh(x, y + k_inner))
                continue;
            ++inner;
            thin += splats.pixels[(size_t(y) * size_t(w) + size_t(x)) * 4 + 3] < k_thin_below ? 1 : 0;
        }
    return inner ? double(thin) / double(inner) : 0.0;
}

core::Result<Coverage> measure_coverage(gpu::Context& ctx, std::span<const Vec4f> x,
                                        std::span<const std::array<uint32_t, 3>> triangles,
                                        std::span<const splat::GaussianRecord> records, render::FrameInputs frame,
                                        uint32_t width, uint32_t height, std::optional<Vec3f> albedo,
                                        std::span<const splat::GaussianShape> shapes, std::span<const Vec3f> colors,
                                        const ReferenceTextures* textures, const SplatTexturing* texturing, size_t one_sided,
                                        const OccluderInput* occluders) {
    Coverage c;
    auto raster = mesh_raster(ctx, x, triangles, width, height, colors);
    if (!raster.ok()) return raster.error();
    auto mask = render_mesh_image(ctx, *raster.value(), frame, render::MeshView::mask);
    if (!mask.ok()) return mask.error();
    c.mesh = std::move(mask->image);
    if (albedo) {
        render::FrameInputs lit = frame;
        lit.background = Vec4f::Zero();
        auto shaded = textures ? textured_image(ctx, x, triangles, *textures, lit, width, height)
                               : lit_image(ctx, *raster.value(), lit, colors.empty() ? *albedo : Vec3f::Ones());
        if (!shaded.ok()) return shaded.error();
        c.shaded = std::move(shaded).value();
    }

    const OccluderInput mesh{x, triangles, one_sided};
    auto splats = splat_image(ctx, occluders ? *occluders : mesh, records, frame, width, height, shapes, texturing);
    if (!splats.ok()) return splats.error();
    c.splats = std::move(splats).value();

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
    c.thin_ratio = thin_ratio(c.splats, c.mesh);
    c.silhouette_iou = double(both) / double(either);
    if (albedo) {
        c.speck_ratio = speck_ratio(c.splats, c.shaded, c.mesh);
        c.shading_error = shading_error(c.splats, c.shaded, c.mesh);
        c.edge_excess = edge_excess(c.splats, c.shaded, c.mesh);
        c.color_error = color_error(c.splats, c.shaded, c.mesh);
    }
    return c;
}

} // namespace pbdsplat::passes
