#pragma once
// The faces a cut made, drawn. The body is a shell (the paper's surface mesh under a volume
// constraint), and a cut that keeps its pieces closed ("cap" or "rebase") closes each with a cap
// loop that the volume and contact span with a face; drawn as the shell alone, a piece seen from
// its cut side was hollow, its far wall's inside and the background showing through. Each such
// loop is spanned as contact spans it (least-area triangles over the loop as it lay when first
// seen, sim/contact.h) and sampled at the boundary particles' spacing h; the samples ride on the
// loop's particles (barycentric in the face's triangles) and are drawn as splats of the interior
// colour, lit smoothly across each part of the face (a second cut folds it into parts), fading
// in as the cut's own new splats do. A burst's openings (a popped balloon) and a tear's slits
// stay open; a model's own capped holes are not cut faces.
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "mesh/triangle_mesh.h"
#include "sim/soft_body.h"
#include "splat/gaussian_record.h"

namespace pbdsplat::splat {

class CutFaces {
public:
    // `h`: the samples' spacing (no samples, and no faces drawn, at 0); `interior`: the faces'
    // colour (linear rgb) where the scene gives one, else each face takes its rim's (a body's
    // particle colours: each model of a scene its own) or `albedo`; `fade_frames`: the frames a
    // new face takes to fade in; `seed`: the sampler's.
    CutFaces() = default;
    CutFaces(float h, const std::optional<Vec3f>& interior, const Vec3f& albedo, uint32_t fade_frames, uint32_t seed = 1);

    // A cut was made since the last update: the loops that update finds new are its faces. New
    // loops without a cut (a tear's openings, which a user sees open) are not drawn.
    void cut_made() { cut_pending_ = true; }
    // Follows the body's cap loops, once a frame: a loop a cut made gets its face and samples
    // when first seen, a loop gone (cut again, or its piece burst) loses its face.
    void update(const sim::SoftBody& body);

    // One record per sample for positions `x` (the body's particles), appended to `out`; with
    // `shapes`, a flat disc in the face's plane appended for each too.
    // `colors`: the particles' colours, or empty.
    // `model_of_particle` (a scene of several models): each record takes its face's model.
    void append_records(std::span<const Vec4f> x, std::span<const Vec3f> colors, const Appearance& look, std::vector<GaussianRecord>& out,
                        std::vector<GaussianShape>* shapes, std::span<const uint32_t> model_of_particle = {}) const;

    // The faces as a surface: their triangles appended to `triangles`, on corners of their own
    // appended to `out_x`, one per particle of each part of a face (so a mesh drawn from them is
    // lit as the splats are: smoothly within each part, not with the shell's normals at the
    // rim). `out_colors`, when not null, gets each appended corner's colour, the one its face's
    // splats take (`colors`: the particles' colours, or empty).
    void append_surface(std::span<const Vec4f> x, std::vector<Vec4f>& out_x, std::vector<mesh::Triangle>& triangles,
                        std::span<const Vec3f> colors = {}, std::vector<Vec3f>* out_colors = nullptr) const;

    // The triangles (over the body's particles) of the face drawn over `loop`; null if none is.
    const std::vector<mesh::Triangle>* triangles_of(const std::vector<uint32_t>& loop) const;
    size_t faces() const;  // drawn
    // Some face is still fading in (its records change with each update).
    bool fading() const;
    size_t samples() const;

private:
    struct Face {
        std::vector<uint32_t> loop;
        std::vector<mesh::Triangle> triangles;  // over the body's particles; none for a slit
        // Per triangle, the part of the face it spans (mesh::triangulate_across_older): 0 the
        // cut's own, k > 0 an older face's that a second cut folded it from.
        std::vector<uint8_t> part;
        // The face's corners, one per particle of each part (share_corners): their particles,
        // and per triangle corner (3 t + j) which one it is.
        std::vector<uint32_t> corner_particles, corner_of;
        std::vector<uint32_t> sample_triangle;  // per sample: its triangle in `triangles`
        std::vector<Vec2f> bary;                // per sample: (b1, b2) in that triangle
        float first_perimeter = 0.0f, first_area = 0.0f;  // the loop's as first seen
        uint32_t age = 0;                       // frames since it appeared
        bool seen = false;
    };
    // `older`: the sorted particles of the loops known before (sim::face_triangles).
    Face make_face(const std::vector<uint32_t>& loop, const sim::SoftBody& body, std::span<const uint32_t> older) const;
    // Fills f.corner_particles and f.corner_of from its triangles and parts (fixed for its life).
    static void share_corners(Face& f);
    // The face's normal at each of its corners, for positions `x` (its Newell normal `n`, its
    // `area`): the area-weighted mean of its triangles there. The loop is spanned by triangles
    // over its rim alone, at angles that follow the rim as it warps rather than the solid matter
    // the face stands for: lit by each triangle's own normal, a squashed piece's face would show
    // the spanning as flat facets and a sliver's odd angle as a bright spoke. Corners are shared
    // within a part only, so a fold between two cuts stays a crease.
    static void corner_normals(const Face& f, std::span<const Vec4f> x, const Vec3f& n, float area, std::vector<Vec3f>& normals);
    // The face's colour: the interior colour, else the mean of its rim's (`colors` one per
    // particle), else the albedo.
    Vec3f albedo_of(const Face& f, std::span<const Vec3f> colors, size_t particles) const;
    // The face's Newell vector (its normal times twice its area) and its loop's length, now.
    static std::pair<Vec3f, float> measure(const std::vector<uint32_t>& loop, std::span<const Vec4f> x);

    std::vector<Face> faces_;
    float h_ = 0.0f;
    std::optional<Vec3f> interior_;
    Vec3f albedo_ = Vec3f::Ones();
    uint32_t fade_frames_ = 8;
    uint32_t seed_ = 1;
    bool cut_pending_ = false;
};

} // namespace pbdsplat::splat
