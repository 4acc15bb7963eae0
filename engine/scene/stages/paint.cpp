#include "scene/stages/paint.h"

#include <algorithm>
#include <cmath>

#include "core/thread_pool.h"
#include "scene/stages/frame_keys.h"

namespace pbdsplat::scene {

bool SurfacePaint::empty() const {
    return std::none_of(model.begin(), model.end(), [](const auto& m) { return m != nullptr; });
}

std::vector<const asset::Texture*> SurfacePaint::textures() const {
    std::vector<const asset::Texture*> out;
    for (const auto& m : model)
        if (m)
            for (const asset::Texture& t : m->look().textures) out.push_back(&t);
    return out;
}

std::vector<int32_t> SurfacePaint::first_texture() const {
    std::vector<int32_t> out(model.size(), 0);
    int32_t n = 0;
    for (size_t m = 0; m < model.size(); ++m) {
        out[m] = n;
        if (model[m]) n += int32_t(model[m]->look().textures.size());
    }
    return out;
}

std::vector<render::MeshTexture> gpu_textures(std::span<const asset::Texture* const> textures) {
    const auto wrap = [](asset::Wrap w) {
        return w == asset::Wrap::clamp    ? VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE
               : w == asset::Wrap::mirror ? VK_SAMPLER_ADDRESS_MODE_MIRRORED_REPEAT
                                          : VK_SAMPLER_ADDRESS_MODE_REPEAT;
    };
    std::vector<render::MeshTexture> out;
    for (const asset::Texture* t : textures) out.push_back({t->width, t->height, t->rgba, wrap(t->wrap_u), wrap(t->wrap_v)});
    return out;
}

uint32_t pack_color(const Vec3f& c) {
    uint32_t out = 0xFF000000u;
    for (int k = 0; k < 3; ++k) out |= uint32_t(std::lround(std::clamp(c[k], 0.0f, 1.0f) * 255.0f)) << (8 * k);
    return out;
}

namespace {

Vec3f color_of(const SurfacePaint& paint, uint32_t model, const Vec3f& rest, std::vector<mesh::ClosestPoint>& scratch) {
    if (model < paint.model.size() && paint.model[model]) return paint.model[model]->at(rest, scratch);
    return model < paint.plain.size() ? paint.plain[model] : Vec3f::Ones();
}

uint32_t model_of(const sim::BodyStructure& body, uint32_t particle) {
    return particle < body.model_of_particle.size() ? body.model_of_particle[particle] : 0u;
}

} // namespace

void paint_particles(const SurfacePaint& paint, sim::SoftBody& body) {
    body.colors.resize(body.particle_count());
    std::vector<mesh::ClosestPoint> scratch;
    for (uint32_t i = 0; i < body.particle_count(); ++i)
        body.colors[i] = color_of(paint, model_of(body, i), body.rest_positions[i], scratch);
}

std::vector<Vec3f> paint_vertices(const SurfacePaint& paint, const sim::BodyStructure& body, const mesh::TriangleMesh& surface,
                                  const surface::BoundaryParticles& embedded) {
    std::vector<Vec3f> out(surface.vertex_count());
    std::vector<mesh::ClosestPoint> scratch;
    for (size_t v = 0; v < out.size(); ++v) {
        const uint32_t model = v < embedded.size() ? model_of(body, body.triangles[embedded.triangle[v]][0]) : 0u;
        out[v] = color_of(paint, model, surface.positions[v], scratch);
    }
    return out;
}

namespace {

// Barycentrics (b1, b2) of p's projection on the plane of (a, b, c): outside the triangle where
// p is, so a corner of a triangle that is not the look's own reads the look extended.
Vec2f plane_bary(const Vec3f& p, const Vec3f& a, const Vec3f& b, const Vec3f& c) {
    const Vec3f e1 = b - a, e2 = c - a, d = p - a;
    const float d11 = e1.dot(e1), d12 = e1.dot(e2), d22 = e2.dot(e2), det = d11 * d22 - d12 * d12;
    if (!(std::abs(det) > 0.0f)) return Vec2f::Zero();
    const float p1 = d.dot(e1), p2 = d.dot(e2);
    return Vec2f((d22 * p1 - d12 * p2) / det, (d11 * p2 - d12 * p1) / det);
}

} // namespace

TriangleLooks paint_triangles(const SurfacePaint& paint, std::span<const Vec3f> rest, std::span<const uint32_t> vertex_model,
                              std::span<const mesh::Triangle> triangles) {
    TriangleLooks out;
    out.textures = paint.textures();
    if (out.textures.empty()) return out;
    const std::vector<int32_t> first_texture = paint.first_texture();
    out.texture.assign(triangles.size(), -1);
    out.uv.assign(triangles.size(), {Vec2f::Zero(), Vec2f::Zero(), Vec2f::Zero()});
    out.tint.resize(triangles.size());
    std::vector<mesh::ClosestPoint> scratch;
    for (size_t t = 0; t < triangles.size(); ++t) {
        const mesh::Triangle& tri = triangles[t];
        const uint32_t model = tri[0] < vertex_model.size() ? vertex_model[tri[0]] : 0u;
        const asset::SurfaceColors* colors = model < paint.model.size() ? paint.model[model].get() : nullptr;
        const Vec3f plain = model < paint.plain.size() ? paint.plain[model] : Vec3f::Ones();
        out.tint[t] = {plain, plain, plain};
        if (!colors) continue;
        const auto near = colors->nearest((rest[tri[0]] + rest[tri[1]] + rest[tri[2]]) / 3.0f, scratch);
        if (!near) continue;
        const asset::SurfaceLook& look = colors->look();
        const mesh::Triangle& lt = look.triangles[near->triangle];
        for (int k = 0; k < 3; ++k) {
            const Vec2f b = plane_bary(rest[tri[k]], look.positions[lt[0]], look.positions[lt[1]], look.positions[lt[2]]);
            const asset::SurfaceLook::Parts parts = look.parts_at(near->triangle, b);
            out.tint[t][k] = parts.tint.cwiseMax(0.0f);
            out.uv[t][k] = parts.uv;
            if (parts.texture >= 0) out.texture[t] = first_texture[model] + parts.texture;
        }
    }
    return out;
}

namespace {

// A point's colour and, where `textured`, where the texture lies at it: one nearest-point search
// for both.
struct PointLook {
    Vec3f color;
    surface::BoundaryParticles::Texcoord texcoord;
};
PointLook look_of(const SurfacePaint& paint, uint32_t model, bool textured, const std::vector<int32_t>& first_texture,
                  const Vec3f& rest, std::vector<mesh::ClosestPoint>& scratch) {
    const asset::SurfaceColors* colors = model < paint.model.size() ? paint.model[model].get() : nullptr;
    if (!colors) return {color_of(paint, model, rest, scratch), {}};
    const auto near = colors->nearest(rest, scratch);
    if (!near) return {Vec3f::Ones(), {}};
    PointLook out{colors->look().color_at(near->triangle, near->bary), {}};
    if (!textured) return out;
    const auto q = colors->texture_point(*near, rest, paint.texture_reach);
    // The splats read at most SPLAT_MAX_TEXTURES; the points of the rest keep their colour.
    if (!q || first_texture[model] + q->texture >= int32_t(SPLAT_MAX_TEXTURES)) return out;
    out.texcoord = {q->uv, q->gradient.du, q->gradient.dv, q->tint, first_texture[model] + q->texture, q->reach};
    return out;
}

} // namespace

void paint_particle_texcoords(const SurfacePaint& paint, sim::SoftBody& body) {
    body.texcoords.clear();
    if (!(paint.texture_reach > 0.0f) || !paint.textured()) return;
    const std::vector<int32_t> first_texture = paint.first_texture();
    body.texcoords.resize(body.particle_count());
    std::vector<mesh::ClosestPoint> scratch;
    for (uint32_t i = 0; i < body.particle_count(); ++i)
        body.texcoords[i] = look_of(paint, model_of(body, i), true, first_texture, body.rest_positions[i], scratch).texcoord;
}

size_t paint_samples(const SurfacePaint& paint, const sim::BodyStructure& body, surface::BoundaryParticles& s, core::ThreadPool* pool) {
    // What waits for paint is a suffix: samples are only appended, and keep_if keeps the order
    // (padding the colours it compacts with zeros at the end). So a frame costs what it added.
    size_t first = std::min(s.color.size(), s.size());
    while (first > 0 && !(s.color[first - 1] >> 24)) --first;
    s.color.resize(s.size(), 0u);
    const bool textured = paint.texture_reach > 0.0f && paint.textured();
    const std::vector<int32_t> first_texture = textured ? paint.first_texture() : std::vector<int32_t>{};
    if (textured) s.texcoord.resize(s.size());
    const auto run = [&](unsigned, size_t begin, size_t end) {
        std::vector<mesh::ClosestPoint> scratch;
        for (size_t k = first + begin; k < first + end; ++k) {
            const mesh::Triangle& t = body.triangles[s.triangle[k]];
            const Vec3f &a = body.rest_positions[t[0]], &b = body.rest_positions[t[1]], &c = body.rest_positions[t[2]];
            const Vec2f w = s.bary[k];
            Vec3f rest = a + w.x() * (b - a) + w.y() * (c - a);
            // An embedded sample stands off its coarse triangle by its offset: along the face
            // normal is close enough to find the fine surface's spot under it.
            if (s.embedded()) {
                const Vec3f n = (b - a).cross(c - a);
                if (n.squaredNorm() > 0.0f) rest += s.offset[k] * n.normalized();
            }
            const PointLook look = look_of(paint, model_of(body, t[0]), textured, first_texture, rest, scratch);
            s.color[k] = pack_color(look.color);
            if (textured) s.texcoord[k] = look.texcoord;
        }
    };
    const size_t count = s.size() - first;
    if (pool) pool->parallel_for(count, run);
    else run(0, 0, count);
    return count;
}

void add_paint_pass(graph::FrameGraph& g, graph::Blackboard& board, uint32_t tag) {
    struct PaintHandles {
        graph::Handle<sim::BodyStructure> body;  // where the samples lie at rest: the structure alone
        graph::Handle<SurfacePaint> paint;
        graph::Handle<surface::BoundaryParticles> samples;
    } h{board.get(keys::body_structure), board.get(keys::paint), board.get(keys::samples)};
    g.add_pass(
        "paint", graph::PassKind::cpu,
        [&](graph::PassBuilder& b) {
            b.read(h.body);
            b.read(h.paint);
            h.samples = b.write(h.samples);
            return [hh = h](const graph::PassResources& r, graph::ExecuteContext&) {
                paint_samples(r.read(hh.paint), r.read(hh.body), r.write(hh.samples));
            };
        },
        tag);
    board.put(keys::samples, h.samples);
}

} // namespace pbdsplat::scene
