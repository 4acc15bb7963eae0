#include "scene/stages/write_check.h"

#include <cstring>
#include <span>

#include "sim/state_hash.h"

namespace pbdsplat::scene {

namespace {
// FNV-1a over the bytes given, continuing from `h`.
uint64_t mix(uint64_t h, const void* data, size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < bytes; ++i) h = (h ^ p[i]) * 1099511628211ull;
    return h;
}
template <class T>
uint64_t mix_value(uint64_t h, const T& v) {
    return mix(h, &v, sizeof(T));
}
template <class T>
uint64_t mix_span(uint64_t h, std::span<const T> v) {
    h = mix_value(h, v.size());
    return v.empty() ? h : mix(h, v.data(), v.size_bytes());
}
constexpr uint64_t k_basis = 14695981039346656037ull;
} // namespace

uint64_t fingerprint(const sim::BodyStructure& body) {
    uint64_t h = mix_value(k_basis, body.triangles.size());
    h = mix_value(h, body.distance.size());
    h = mix_value(h, body.pieces);
    h = mix_span<uint32_t>(h, body.piece_of_particle);
    for (const sim::VolumeConstraint& v : body.volumes) h = mix_value(mix_value(mix_value(h, v.piece), v.pressure), v.rest_volume);
    return h;
}

uint64_t fingerprint(const sim::BodyState& state) { return mix_value(k_basis, sim::state_hash(state.particles)); }

uint64_t fingerprint(const sim::BodyCaches& caches) { return mix_span<Vec3f>(k_basis, caches.normals); }

uint64_t fingerprint(const sim::DragConstraint& d) {
    uint64_t h = mix_span<uint32_t>(k_basis, d.particles);
    h = mix_span<float>(h, d.weights);
    for (const Vec3f& o : d.offsets) h = mix(h, o.data(), sizeof(float) * 3);
    h = mix(h, d.target.data(), sizeof(float) * 3);
    return mix_value(h, d.active);
}

uint64_t fingerprint(const splat::Appearance& a) {
    uint64_t h = mix(k_basis, a.albedo.data(), sizeof(float) * 3);
    return mix_value(mix_value(h, a.opacity_logit), a.scale);
}

uint64_t fingerprint(const surface::BoundaryParticles& s) {
    uint64_t h = mix_span<uint32_t>(k_basis, s.triangle);
    h = mix_span<Vec2f>(h, s.bary);
    h = mix_span<uint32_t>(h, s.color);
    return mix_span<float>(h, s.fade);
}

uint64_t fingerprint(const render::FrameInputs& frame) {
    const render::Camera& c = frame.camera;
    const uint64_t h = mix(k_basis, c.eye.data(), sizeof(float) * 3);
    return mix(h, c.target.data(), sizeof(float) * 3);
}

uint64_t fingerprint(const passes::SplatStream& splats) { return mix_span<splat::GaussianRecord>(k_basis, splats.records); }

uint64_t fingerprint(const std::string& text) { return mix(k_basis, text.data(), text.size()); }

uint64_t fingerprint(const MapSettings& s) {
    uint64_t h = mix_value(mix_value(mix_value(k_basis, s.particles), s.show_boundary), s.closed);
    h = mix_value(mix_value(h, s.cull_back), s.draw_ground);
    return mix_value(h, s.ground.has_value());
}

uint64_t fingerprint(const FrameChanges& c) {
    uint64_t h = mix_value(mix_value(k_basis, c.changes.size()), c.seed_offset);
    for (const FrameChanges::Change& x : c.changes) h = mix_value(mix_value(h, x.change.particles_after), x.change.triangles_after);
    return mix_span<uint32_t>(h, c.refill);
}

} // namespace pbdsplat::scene
