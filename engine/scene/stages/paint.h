#pragma once
// A model's own look on its splats: each particle and boundary particle takes the colour of the
// spot of the model's full-resolution surface where it lies at rest (asset/surface_colors.h).
// Only scenes whose models have a look (a texture, materials, vertex colours) schedule it.
#include <array>
#include <memory>
#include <span>
#include <vector>

#include "asset/surface_colors.h"
#include "render/mesh_textures.h"
#include "graph/blackboard.h"
#include "graph/frame_graph.h"
#include "sim/soft_body.h"
#include "surface/boundary_particles.h"

namespace pbdsplat::core {
class ThreadPool;
}

namespace pbdsplat::scene {

struct SurfacePaint {
    // Per model of the scene ([model], then each [[bodies]] entry): its look, or null for a
    // plain one, drawn in `plain`'s colour.
    std::vector<std::shared_ptr<const asset::SurfaceColors>> model;
    std::vector<Vec3f> plain;
    // How far a splat reaches about its sample (world units, rest frame): where above 0, the
    // samples of textured models also carry where the texture lies on them (BoundaryParticles::
    // texcoord), for splats that read it per pixel, no farther than a seam within this.
    float texture_reach = 0.0f;

    bool empty() const;  // no model has a look
    // Every model's textures, in model order, and where each model's first one is in that list.
    std::vector<const asset::Texture*> textures() const;
    std::vector<int32_t> first_texture() const;
    bool textured() const { return !textures().empty(); }
};

// Textures as the GPU takes them (the bytes stay the assets'), wrap modes translated.
std::vector<render::MeshTexture> gpu_textures(std::span<const asset::Texture* const> textures);

// Linear RGB as the records' bytes, alpha 255 (painted).
uint32_t pack_color(const Vec3f& c);

// Every particle's colour (SoftBody::colors) from where it lies at rest.
void paint_particles(const SurfacePaint& paint, sim::SoftBody& body);
// Where the texture lies at every particle (SoftBody::texcoords), for particles drawn as splats
// that read it per pixel (paint.texture_reach set); clears them otherwise.
void paint_particle_texcoords(const SurfacePaint& paint, sim::SoftBody& body);
// The colour of each vertex of `surface` (the models' fine surface, in the body's rest frame);
// `embedded` (one sample per vertex, on the body's triangles) tells each vertex's model.
std::vector<Vec3f> paint_vertices(const SurfacePaint& paint, const sim::BodyStructure& body, const mesh::TriangleMesh& surface,
                                  const surface::BoundaryParticles& embedded);
// A textured model's look on triangles, apart, for a renderer that samples the textures (the
// lit reference of `pbdsplat check`): per triangle its texture (into `textures`, -1 for none),
// per corner the texture coordinates and the colour the texture multiplies.
struct TriangleLooks {
    std::vector<int32_t> texture;
    std::vector<std::array<Vec2f, 3>> uv;
    std::vector<std::array<Vec3f, 3>> tint;
    std::vector<const asset::Texture*> textures;  // every model's, in model order
};
// The looks of `triangles` over vertices at rest at `rest` (in the body's rest frame), each
// vertex of model `vertex_model[v]` (model 0 past its end): each triangle takes the look of the
// model's triangle nearest its centre, read at its corners. Empty where no model has a texture.
TriangleLooks paint_triangles(const SurfacePaint& paint, std::span<const Vec3f> rest, std::span<const uint32_t> vertex_model,
                              std::span<const mesh::Triangle> triangles);
// The samples that have no colour yet (those added since the last call: always the last ones);
// returns how many were painted. The same colours with or without a pool.
size_t paint_samples(const SurfacePaint& paint, const sim::BodyStructure& body, surface::BoundaryParticles& samples,
                     core::ThreadPool* pool = nullptr);

namespace keys {
inline constexpr graph::Key<SurfacePaint> paint{"paint"};
}
// The pass that paints what a cut, a tear or the density control added this frame: reads the
// body and keys::paint from `board`, writes the samples.
void add_paint_pass(graph::FrameGraph& g, graph::Blackboard& board, uint32_t tag);

} // namespace pbdsplat::scene
