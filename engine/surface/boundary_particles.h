#pragma once
// Boundary particles (paper sections 4.2 and 5.3): samples of the surface, at least h apart
// and leaving no point of it farther than about h from a sample, with h = eta * l_edge (eq. 3).
// Each is stored as (triangle, barycentric coordinates) and follows the deforming mesh:
// x = sum b_i x_i, n = normalise(sum b_i n_i). The mesh vertices (the simulation particles)
// count as samples too, so boundary particles fill the space between them.
//
// When the simulation mesh is a decimated copy of a detailed model, the samples come from the
// detailed surface and are embedded in the coarse one (surface/embedding.h): each also has a
// signed offset d along the interpolated vertex normal, x = sum b_i x_i + d sum b_i n_i, and
// its own normal in its triangle's frame, so the fine shape rides on the coarse physics.
#include <cstdint>
#include <span>
#include <vector>

#include "core/math.h"
#include "mesh/surface_texcoord.h"
#include "mesh/triangle_mesh.h"

namespace pbdsplat::core {
class ThreadPool;
}

namespace pbdsplat::surface {

struct BoundaryParticles {
    // Compact arrays, one entry per sample.
    std::vector<uint32_t> triangle;
    std::vector<Vec2f> bary;  // (b1, b2); b0 = 1 - b1 - b2
    // Embedded samples only (both empty otherwise, both one entry per sample): the offset along
    // the interpolated vertex normal, and the rest normal in the triangle's frame
    // (edge 0-1, in-plane perpendicular, face normal).
    std::vector<float> offset;
    std::vector<Vec3f> local_normal;
    // Updated every frame.
    std::vector<Vec3f> position;
    std::vector<Vec3f> normal;
    // Samples fading in (new ones) or out (retired ones): the splat's opacity factor in [0, 1]
    // and its change per frame (negative: retiring, removed once it reaches 0). Shorter than the
    // other arrays (or empty) when the samples past its end were added at full opacity:
    // samplers append without knowing about fades; padded() fills the rest with (1, 0).
    std::vector<float> fade;
    std::vector<float> fade_step;
    // The splat size of each sample relative to the material's (edge samples are smaller, see
    // surface/edges.h); shorter than the other arrays (or empty) where it is 1, as for fades.
    std::vector<float> size_factor;
    // The base colour of each sample where the model has a look of its own (a texture, materials,
    // vertex colours): linear RGB as bytes, alpha 255 once painted (scene/stages/paint.h). Empty
    // for a plain material; shorter than the other arrays, or 0, where a sample waits for paint.
    std::vector<uint32_t> color;
    // Where a textured model's texture lies on each sample, for splats that read it per pixel
    // (mesh/surface_texcoord.h; scene/stages/paint.h). Empty unless a model is textured; painted
    // with `color`.
    using Texcoord = mesh::SurfaceTexcoord;
    std::vector<Texcoord> texcoord;
    // Each sample's level in the thinning order (surface/thin_order.h); shorter (or empty) where
    // not yet given. Where samples of a level above 0 were removed, their positions (the gaps
    // they leave in the order, to fill around).
    std::vector<uint8_t> thin_level;
    std::vector<Vec3f> thin_gaps;
    // Per simulation triangle, not per sample: how far it has stretched past the density
    // control's refill threshold since its samples were placed (>= 1; empty, or past its end: 1).
    // Its splats grow by as much, so a surface pulled wider than its samples reach stays closed
    // until the control refills it (surface/density.h).
    std::vector<float> triangle_growth;

    size_t size() const { return triangle.size(); }
    bool embedded() const { return !offset.empty(); }
    void clear();
    float fade_of(size_t i) const { return i < fade.size() ? fade[i] : 1.0f; }
    bool retiring(size_t i) const { return i < fade_step.size() && fade_step[i] < 0.0f; }
    float size_of(size_t i) const { return i < size_factor.size() ? size_factor[i] : 1.0f; }
    float growth_of(uint32_t t) const { return t < triangle_growth.size() ? triangle_growth[t] : 1.0f; }
    bool on_edge(size_t i) const { return size_of(i) < 1.0f; }
    // Extends the fade arrays to every sample.
    void pad_fades() {
        fade.resize(size(), 1.0f);
        fade_step.resize(size(), 0.0f);
    }
    // Keeps the samples for which keep(i) is true, in order, in every array.
    template <class Keep>
    size_t keep_if(const Keep& keep);
};

struct SamplingOptions {
    float h = 0.05f;         // minimum spacing
    uint32_t seed = 1;       // same seed, same samples
    float candidates = 48.0f;  // candidate points per h^2 of area: enough that no gap wider than about h stays
};

// The spacing for a mesh: eta times its mean rest edge length.
float spacing(const mesh::TriangleMesh& mesh, float eta);

// A maximal sample set at spacing h covers its surface with one sample per this many h^2 of
// area: a random maximal set packs looser than the hexagonal 0.87 h^2 (at 1.54 a fine sphere got
// 0.98-1.005 of the budget asked for, tests/surface/test_boundary_particles.cpp).
inline constexpr float k_area_per_sample = 1.54f;
// The spacing at which a maximal sample set of `mesh` holds about `budget` samples: the floor a
// sample budget sets under eta times the edge, so a detailed scan (a million triangles, each
// edge a fraction of a millimetre) is drawn with as many splats as the budget, not as many as it
// has triangles. 0 for no budget (0) or no area.
float spacing_for_budget(const mesh::TriangleMesh& mesh, size_t budget);

// Samples the whole surface. The mesh's vertices act as samples already placed.
BoundaryParticles sample_surface(const mesh::TriangleMesh& mesh, const SamplingOptions& options);

// A sample of a surface as a free point: position and (interpolated vertex) normal.
struct SurfacePoint {
    Vec3f position;
    Vec3f normal;
};
// Samples the whole of `surface` with the same maximal sampler; `anchors` act as samples
// already placed (the simulation particles of a coarser mesh that carries this surface). The
// same samples with or without a pool.
std::vector<SurfacePoint> sample_points(const mesh::TriangleMesh& surface, std::span<const Vec3f> anchors,
                                        const SamplingOptions& options, core::ThreadPool* pool = nullptr);

// Adds samples on the given triangles only, keeping h away from every sample already present
// (anywhere) and from the vertices; existing samples do not move. For local resampling after a
// cut or tear.
void fill_triangles(const mesh::TriangleMesh& mesh, std::span<const uint32_t> triangles, const SamplingOptions& options,
                    BoundaryParticles& samples);
// The same on a surface given as rest positions and triangles (a body's, without copying them).
void fill_triangles(std::span<const Vec3f> positions, std::span<const mesh::Triangle> all_triangles,
                    std::span<const uint32_t> triangles, const SamplingOptions& options, BoundaryParticles& samples);
// The same with other points than the vertices counting as samples already placed (none when
// the vertices are not drawn: a coarse simulation mesh carrying an embedded surface), and,
// when `piece` (one entry per triangle) is given, samples blocking only within their piece: at
// the moment of a cut its two sides coincide, and one side's samples leave with their piece.
void fill_triangles(std::span<const Vec3f> positions, std::span<const mesh::Triangle> all_triangles,
                    std::span<const uint32_t> triangles, std::span<const Vec3f> anchors, std::span<const uint32_t> piece,
                    const SamplingOptions& options, BoundaryParticles& samples);

// Gives samples [first, size()) of an embedded set the embedding of their triangles' nearest
// older samples (interpolate_embedding); nothing for a set that is not embedded.
void embed_appended(size_t first, BoundaryParticles& samples);

// Moves every sample onto the deformed surface: positions from `x` (one float4 per mesh vertex,
// w ignored), normals from the vertex normals (embedded samples: offset along the interpolated
// normal, own normal turned with the triangle's frame).
// The orthonormal frame of triangle (a, b, c): columns edge a-b, in-plane perpendicular, normal.
Mat3f triangle_frame(const Vec3f& a, const Vec3f& b, const Vec3f& c);
// The frame an embedded sample's own normal is kept in: columns edge a-b made perpendicular to
// `normal` (the interpolated vertex normal at the sample, any length), their cross product, and
// that normal. It turns from triangle to triangle as smoothly as the interpolated normal does;
// the face's frame jumped at every coarse edge, and a crumpled coarse mesh showed its triangles
// as facets in the fine surface's shading. triangle_frame where `normal` is degenerate.
Mat3f surface_frame(const Vec3f& a, const Vec3f& b, const Vec3f& c, const Vec3f& normal);

// Samples [first, size()) only (the ones just added), when the others are current.
// `pool`: threads that take ranges of the samples (the result is the same). `moved` (one entry
// per triangle, or empty for all): the samples on a triangle marked 0 are current already and
// are left as they are (their triangle's piece has not moved since they were carried).
void update_boundary_particles(std::span<const mesh::Triangle> triangles, std::span<const Vec4f> x,
                               std::span<const Vec3f> vertex_normals, BoundaryParticles& samples, size_t first = 0,
                               core::ThreadPool* pool = nullptr, std::span<const uint8_t> moved = {});
// Positions alone (what a mesh drawn from them needs): update_boundary_particles without the
// normals' frames, most of its cost.
void update_boundary_positions(std::span<const mesh::Triangle> triangles, std::span<const Vec4f> x, std::span<const Vec3f> n,
                               BoundaryParticles& s);

template <class Keep>
size_t BoundaryParticles::keep_if(const Keep& keep) {
    if (!fade.empty()) pad_fades();
    if (!size_factor.empty()) size_factor.resize(size(), 1.0f);
    if (!color.empty()) color.resize(size(), 0u);
    if (!texcoord.empty()) texcoord.resize(size());
    if (!thin_level.empty()) thin_level.resize(size(), 0u);
    // The kept prefix stays where it is: a local edit drops few samples, late in the arrays.
    size_t first = 0;
    while (first < size() && keep(first)) ++first;
    if (first == size()) return 0;
    const auto gap = [this](size_t i) {
        if (i < thin_level.size() && thin_level[i] > 0 && position.size() == size()) thin_gaps.push_back(position[i]);
    };
    gap(first);
    size_t out = first;
    const bool off = !offset.empty(), nl = !local_normal.empty(), pos = position.size() == size(), fd = !fade.empty(),
               sz = !size_factor.empty(), col = !color.empty(), tc = !texcoord.empty(), lv = !thin_level.empty();
    for (size_t i = first + 1; i < size(); ++i) {
        if (!keep(i)) {
            gap(i);
            continue;
        }
        triangle[out] = triangle[i];
        bary[out] = bary[i];
        if (off) offset[out] = offset[i];
        if (nl) local_normal[out] = local_normal[i];
        if (pos) position[out] = position[i], normal[out] = normal[i];
        if (fd) fade[out] = fade[i], fade_step[out] = fade_step[i];
        if (sz) size_factor[out] = size_factor[i];
        if (col) color[out] = color[i];
        if (tc) texcoord[out] = texcoord[i];
        if (lv) thin_level[out] = thin_level[i];
        ++out;
    }
    const size_t dropped = size() - out;
    triangle.resize(out);
    bary.resize(out);
    if (off) offset.resize(out);
    if (nl) local_normal.resize(out);
    if (pos) position.resize(out), normal.resize(out);
    if (fd) fade.resize(out), fade_step.resize(out);
    if (sz) size_factor.resize(out);
    if (col) color.resize(out);
    if (tc) texcoord.resize(out);
    if (lv) thin_level.resize(out);
    return dropped;
}

} // namespace pbdsplat::surface
