#include "scene/stages/body_view.h"

#include <algorithm>

namespace pbdsplat::scene {

void follow_body(std::span<const Vec4f> x, const std::optional<sim::GroundPlane>& plane, const BodyViewOptions& o,
                 render::FrameInputs& frame) {
    // The far side of a closed, opaque body cannot show: its splats are skipped. The threshold
    // keeps those just past the silhouette, whose discs still reach beyond the rim.
    frame.style.cull_facing = o.cull_back && o.closed && o.opaque ? -0.3f : -2.0f;
    // The body's centre, for what reads it: position-based environment lookups look out from
    // it, and the ground's contact shadow lies under it.
    render::Environment& env = frame.lighting.environment;
    const bool env_centre = env.sampling == render::EnvSampling::position || env.sampling == render::EnvSampling::hybrid;
    const bool ground = o.draw_ground && plane && !x.empty();
    Vec3f centre = Vec3f::Zero();
    if (env_centre || ground) {
        for (const Vec4f& p : x) centre += p.head<3>();
        centre /= float(std::max<size_t>(1, x.size()));
    }
    if (env_centre) env.center = centre;
    frame.ground.visible = ground;
    if (ground) fit_ground(*plane, x, centre, frame.ground);
}

void fit_ground(const sim::GroundPlane& plane, std::span<const Vec4f> x, const Vec3f& centre, render::Ground& g) {
    g.normal = plane.normal;
    g.offset = plane.offset;
    // The body's reach along the plane and how high it floats: the contact shadow is darkest
    // for a body lying on the ground and fades as it lifts off.
    const Vec3f n = plane.normal;
    float reach = 0.0f, clearance = 1e30f;
    for (const Vec4f& p : x) {
        const Vec3f d = p.head<3>() - centre;
        reach = std::max(reach, (d - d.dot(n) * n).norm());
        clearance = std::min(clearance, n.dot(p.head<3>()) - plane.offset);
    }
    g.shadow_centre = centre - (n.dot(centre) - plane.offset) * n;
    g.shadow_radius = std::max(reach, 1e-3f);
    g.shadow_strength = 0.55f * std::clamp(1.0f - clearance / std::max(reach, 1e-3f), 0.0f, 1.0f);
    g.centre = g.shadow_centre;
    g.radius = 12.0f * std::max(reach, 0.1f);
}

} // namespace pbdsplat::scene
