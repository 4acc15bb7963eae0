#include "scene/stages/body_view.h"

#include <algorithm>
#include <vector>

namespace pbdsplat::scene {

namespace {
// Each model's centre (position-based lookups look out from a model's own: another moving does
// not relight it); none for a body of one model. Past the last entry the shaders hold, the
// models share it, which then holds the centre of them all.
void model_centres(const BodyPoints& body, const Vec3f& all, std::vector<Vec3f>& out) {
    const uint32_t models = body.model.size() == body.x.size() ? *std::max_element(body.model.begin(), body.model.end()) + 1 : 1;
    if (models < 2) return;
    std::vector<Vec3f> sum(models, Vec3f::Zero());
    std::vector<uint32_t> count(models, 0);
    for (size_t i = 0; i < body.x.size(); ++i) sum[body.model[i]] += body.x[i].head<3>(), ++count[body.model[i]];
    out.resize(std::min<size_t>(models, SPLAT_ENV_CENTERS));
    for (size_t m = 0; m < out.size(); ++m) out[m] = count[m] > 0 ? Vec3f(sum[m] / float(count[m])) : all;
    if (models > SPLAT_ENV_CENTERS) out.back() = all;
}
} // namespace

void follow_body(const BodyPoints& body, const std::optional<sim::GroundPlane>& plane, const BodyViewOptions& o,
                 render::FrameInputs& frame) {
    // The far side of a closed, opaque body cannot show: its splats are skipped. The threshold
    // keeps those just past the silhouette, whose discs still reach beyond the rim.
    frame.style.cull_facing = o.cull_back && o.closed && o.opaque ? -0.3f : -2.0f;
    // The body's centre, for what reads it: position-based environment lookups look out from
    // it, and the ground's disc lies under it.
    render::Environment& env = frame.lighting.environment;
    const bool env_centre = env.sampling == render::EnvSampling::position || env.sampling == render::EnvSampling::hybrid;
    const bool ground = o.draw_ground && plane && !body.x.empty();
    Vec3f centre = Vec3f::Zero();
    if (env_centre || ground) {
        for (const Vec4f& p : body.x) centre += p.head<3>();
        centre /= float(std::max<size_t>(1, body.x.size()));
    }
    if (env_centre) env.center = centre;
    env.model_centers.clear();
    if (env_centre && !body.model.empty()) model_centres(body, centre, env.model_centers);
    frame.ground.visible = ground;
    if (ground) fit_ground(*plane, body, centre, frame.ground);
}

namespace {
// Where a group of particles stands over the plane: its centre, its reach along the plane and
// how high its lowest particle floats.
struct Footing {
    Vec3f sum = Vec3f::Zero();
    size_t count = 0;
    float reach = 0.0f, clearance = 1e30f;
    Vec3f centre() const { return sum / float(std::max<size_t>(1, count)); }
};

render::Ground::Shadow shadow_of(const sim::GroundPlane& plane, const Footing& f) {
    // Darkest for a piece lying on the ground, fading as it lifts off.
    const Vec3f n = plane.normal, c = f.centre();
    render::Ground::Shadow s;
    s.centre = c - (n.dot(c) - plane.offset) * n;
    s.radius = std::max(f.reach, 1e-3f);
    s.strength = 0.55f * std::clamp(1.0f - f.clearance / s.radius, 0.0f, 1.0f);
    return s;
}
} // namespace

void fit_ground(const sim::GroundPlane& plane, const BodyPoints& body, const Vec3f& centre, render::Ground& g) {
    g.normal = plane.normal;
    g.offset = plane.offset;
    const Vec3f n = plane.normal;
    const auto along_plane = [&](const Vec3f& d) { return (d - d.dot(n) * n).norm(); };
    const bool by_piece = body.pieces > 1 && body.piece.size() == body.x.size();
    const auto piece_of = [&](size_t i) { return by_piece ? body.piece[i] : 0u; };
    std::vector<Footing> pieces(by_piece ? body.pieces : 1);
    for (size_t i = 0; i < body.x.size(); ++i)
        if (const uint32_t k = piece_of(i); k < pieces.size()) pieces[k].sum += body.x[i].head<3>(), ++pieces[k].count;
    float reach = 0.0f;
    for (size_t i = 0; i < body.x.size(); ++i) {
        const Vec3f p = body.x[i].head<3>();
        reach = std::max(reach, along_plane(p - centre));
        const uint32_t k = piece_of(i);
        if (k >= pieces.size()) continue;
        Footing& f = pieces[k];
        f.reach = std::max(f.reach, along_plane(p - f.centre()));
        f.clearance = std::min(f.clearance, n.dot(p) - plane.offset);
    }
    // The pieces whose shadows weigh most (strength over area), at most GROUND_SHADOWS of them.
    std::vector<render::Ground::Shadow> shadows;
    for (const Footing& f : pieces)
        if (f.count > 0) shadows.push_back(shadow_of(plane, f));
    const auto weight = [](const render::Ground::Shadow& s) { return s.strength * s.radius * s.radius; };
    std::ranges::stable_sort(shadows, [&](const auto& a, const auto& b) { return weight(a) > weight(b); });
    g.shadows = {};
    for (size_t k = 0; k < std::min(shadows.size(), g.shadows.size()); ++k) g.shadows[k] = shadows[k];
    // The disc keeps its place while the body's footprint stays in its inner third, and grows
    // with it but never shrinks, so the floor's fading rim neither slides nor breathes as pieces
    // move: three models thrown at each other from 3 m apart pulled it in from 36 m to 7 m
    // within ten frames. Where the footprint leaves the inner third, the disc moves just enough.
    const Vec3f c = centre - (n.dot(centre) - plane.offset) * n;
    const float foot = std::max(reach, 0.1f);
    if (!g.fitted) {
        g.centre = c, g.radius = 12.0f * foot, g.fitted = true;
        return;
    }
    g.radius = std::max(g.radius, 12.0f * foot);
    const Vec3f d = c - g.centre;
    const float room = g.radius / 3.0f - foot, dist = d.norm();
    if (dist > room) g.centre += d * ((dist - room) / dist);
}

} // namespace pbdsplat::scene
