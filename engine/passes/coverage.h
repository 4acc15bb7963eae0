#pragma once
// How well the splats cover the surface they stand for, against a raster of the same deformed
// mesh from the same camera: the hole ratio (share of the mesh's pixels where the splats'
// accumulated alpha stays below 0.5), the thin ratio (share of the mesh's inner pixels where it
// stays below 0.9) and the silhouette IoU (splat mask alpha >= 0.5 against the mesh mask).
#include <span>

#include "core/image.h"
#include "gpu/context.h"
#include "passes/gpu_passes.h"
#include "render/frame_inputs.h"
#include "render/mesh_textures.h"
#include "splat/gaussian_record.h"

namespace pbdsplat::passes {

struct Coverage {
    double hole_ratio = 0.0;
    // Share of the mesh's inner pixels (whole 5x5 neighbourhoods inside its mask: not the outline,
    // where the splats fade out by design) that the splats cover less than 0.9: the background
    // showing dimly through, as dark worms between samples a stretched surface has pulled apart.
    // Too faint for the hole ratio and, darker by a tenth to a half, for the specks.
    double thin_ratio = 0.0;
    double silhouette_iou = 0.0;
    double speck_ratio = -1.0;  // -1: not measured (no albedo given)
    double shading_error = -1.0;  // the same
    double color_error = -1.0;    // the same
    double edge_excess = -1.0;    // the same
    size_t mesh_pixels = 0;
    core::ImageRgba8 splats, mesh;  // the two images, for people to look at
    core::ImageRgba8 shaded;        // the lit mesh (with an albedo only)
};

// The thin ratio of a splat image against the mesh's mask (see Coverage::thin_ratio).
double thin_ratio(const core::ImageRgba8& splats, const core::ImageRgba8& mesh_mask);

// Rec. 709 luma of an sRGB-encoded pixel, as bytes: the speck measure's brightness.
double pixel_luminance(const uint8_t* rgba);
// The speck ratio of a splat image (over a black background) against the lit mesh and its mask.
// `marked`, when given, receives the splat image with every speck painted magenta.
double speck_ratio(const core::ImageRgba8& splats, const core::ImageRgba8& shaded_mesh, const core::ImageRgba8& mesh_mask,
                   core::ImageRgba8* marked = nullptr);

// How far the splats' shading is from the lit mesh's: the mean absolute difference of their
// luma (0-1) over the mesh's front pixels. The speck ratio counts only pixels darker than half;
// this also sees a body drawn as facets (each splat lit with one normal) or bright discs.
double shading_error(const core::ImageRgba8& splats, const core::ImageRgba8& shaded_mesh, const core::ImageRgba8& mesh_mask);
// The same over the colour: the mean absolute difference of R, G and B (0-1), so a texture
// drawn in the wrong place or blurred counts where the luma alone might not.
double color_error(const core::ImageRgba8& splats, const core::ImageRgba8& shaded_mesh, const core::ImageRgba8& mesh_mask);

// Structure the splats draw that the lit mesh does not: the share of the mesh's front pixels
// (whole 5x5 neighbourhoods of front: not the silhouette) where the splats' luma less the mesh's
// departs from that difference's neighbourhood mean by more than 4/255. A smooth surface drawn
// smoothly scores 0, whatever its tone; the seam of mismatched discs or scales raise it where the
// mean shading error hardly moves (a thin ragged band is few pixels of a mean). Meant for smooth
// bodies: on a crumpled one the faceted mesh's own creases, which the splats round, count too
// (the deflated default balloon: 0.32); and mottling finer than the check's pixels goes unseen.
double edge_excess(const core::ImageRgba8& splats, const core::ImageRgba8& shaded_mesh, const core::ImageRgba8& mesh_mask);

// A textured look per triangle of the mesh measured: its texture (into `textures`, -1 for
// none), and per corner the texture coordinates and the colour the texture multiplies.
struct ReferenceTextures {
    std::span<const int32_t> triangle_texture;
    std::span<const std::array<Vec2f, 3>> uv;
    std::span<const std::array<Vec3f, 3>> tint;
    std::span<const render::MeshTexture> textures;
};

// Splats that read a textured model's texture per pixel: where it lies on each record, and the
// textures (splat/texcoords.h).
struct SplatTexturing {
    std::span<const splat::GaussianTexcoord> texcoords;
    std::span<const render::MeshTexture> textures;
};

core::Result<Coverage> measure_coverage(gpu::Context& ctx, std::span<const Vec4f> x,
                                        std::span<const std::array<uint32_t, 3>> triangles,
                                        std::span<const splat::GaussianRecord> records, render::FrameInputs frame,
                                        uint32_t width, uint32_t height, std::optional<Vec3f> albedo = std::nullopt,
                                        std::span<const splat::GaussianShape> shapes = {}, std::span<const Vec3f> colors = {},
                                        const ReferenceTextures* textures = nullptr, const SplatTexturing* texturing = nullptr,
                                        size_t one_sided = 0, const OccluderInput* occluders = nullptr);
// `one_sided`: the leading triangles the splats' mesh occluders draw front faces only, as the
// runtime does (render/occluder_pass.h). `occluders`, when given, is what the splats' occluders
// draw instead of the mesh (the runtime's simplified surface on a CPU device). `colors`, when given (one per vertex of x, linear), is
// the model's own look: the lit mesh is drawn in it, as its splats are, instead of in `albedo`. `textures`, when given, draws a
// textured model's look as its file does: each pixel samples the texture (colors then unused).

} // namespace pbdsplat::passes
