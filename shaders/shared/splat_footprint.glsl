// The screen-space footprint of one isotropic Gaussian (paper section 5.5), shared by the
// geometry-shader, mesh-shader and vertex-pulling paths so the three draw the same carriers.
// Needs `frame` (FrameUniforms) declared before inclusion.
#ifndef PBDSPLAT_SPLAT_FOOTPRINT_GLSL
#define PBDSPLAT_SPLAT_FOOTPRINT_GLSL

#include "splat_codec.glsl"
#include "splat_shape.glsl"

// What the fragment stage keeps (SPLAT_FOOTPRINT_* in gpu_types.h): the soft Gaussian, cut where
// its alpha falls below 1/255, or the paper's flat disc (eqs. 22-23: the unit ellipse of the
// quad's coordinates divided by the sharpness, constant opacity), drawn in one depth-tested pass.
layout(constant_id = 2) const uint k_footprint = SPLAT_FOOTPRINT_GAUSSIAN;
// The carrier: a quad (two triangles), or an octagon hugging the ellipse (six triangles,
// 17 % less area); the geometry and mesh paths draw either.
layout(constant_id = 3) const bool k_octagon = false;

const float k_alpha_floor = 1.0 / 255.0;

struct SplatQuad {
    vec3 centre;      // view space (eq. 15), pushed back in the visibility pass
    vec3 axis_right;  // view space, half-size along r (eq. 19)
    vec3 axis_up;     // view space, half-size along u_perp (eq. 20)
    float extent;     // the carrier covers uv in [-extent, extent]^2; 0: nothing to draw
    vec3 plane;       // view space: a surfel's unit normal (its corners' depths lie on its plane);
                      // zero for a round splat (every corner at the centre's depth)
};

// Half-size of the carrier in units of the splat's standard deviation s0. The Gaussian's reach
// is where alpha * exp(-r^2/2) falls below the least alpha that still shows (1/255 in the colour
// pass, render.depth_min_alpha in the depth-only visibility pass): r = sqrt(2 ln(alpha/floor)),
// so faint splats draw small carriers and fully faded ones none. A positive kappa caps it.
// The paper's disc spans kappa s0 (the quad of eqs. 19-20 with l = kappa s0).
float splat_reach(float alpha, bool visibility_pass) {
    if (k_footprint == SPLAT_FOOTPRINT_PAPER) return frame.splat.x;
    const float floor_alpha = visibility_pass ? frame.visibility.z : k_alpha_floor;
    if (!(alpha > floor_alpha)) return 0.0;
    float r = sqrt(2.0 * log(alpha / floor_alpha)) * max(frame.splat.y, frame.splat.z);
    if (frame.splat.x > 0.0) r = min(r, frame.splat.x);
    return r;
}

// Carrier corners in [-1,1]^2 units. The octagon's apothem is 1, so it bounds the unit circle;
// both lists are in triangle-strip order (a zig-zag across the convex outline).
const vec2 k_quad_corners[4] = vec2[4](vec2(-1.0, -1.0), vec2(1.0, -1.0), vec2(-1.0, 1.0), vec2(1.0, 1.0));
const float k_oct_a = 1.0, k_oct_b = 0.41421356;  // tan(22.5 deg)
const vec2 k_octagon_corners[8] = vec2[8](vec2(-k_oct_b, -k_oct_a), vec2(k_oct_b, -k_oct_a), vec2(-k_oct_a, -k_oct_b),
                                          vec2(k_oct_a, -k_oct_b), vec2(-k_oct_a, k_oct_b), vec2(k_oct_a, k_oct_b),
                                          vec2(-k_oct_b, k_oct_a), vec2(k_oct_b, k_oct_a));
const int k_carrier_corners = k_octagon ? 8 : 4;
vec2 carrier_corner(int i) { return k_octagon ? k_octagon_corners[i] : k_quad_corners[i]; }

// The view-plane frame of the paper's quad (eqs. 14-18): the local axes s0*R seen in view space,
// the weakest dropped (eq. 16), the other two made orthonormal by a 2D Gram-Schmidt (eqs.
// 17-18). Only the orientation is kept: for an isotropic Gaussian it matters only where the
// sharpness differs between the quad's two axes.
void paper_frame(vec3 c0, float s0, out vec2 r, out vec2 u) {
    const mat3 rv = mat3(frame.view);
    const vec3 a[3] = vec3[3](s0 * rv[0], s0 * rv[1], s0 * rv[2]);
    const float ck[3] = float[3](dot(a[0].xy, a[0].xy), dot(a[1].xy, a[1].xy), dot(a[2].xy, a[2].xy));
    int weakest = 0;
    if (ck[1] < ck[weakest]) weakest = 1;
    if (ck[2] < ck[weakest]) weakest = 2;
    const int iu = ck[(weakest + 1) % 3] >= ck[(weakest + 2) % 3] ? (weakest + 1) % 3 : (weakest + 2) % 3;
    const int iv = 3 - weakest - iu;
    const float eps = 1e-6;
    const vec2 u2 = a[iu].xy;
    r = u2 / (length(u2) + eps);
    const vec2 v2 = a[iv].xy;
    const vec2 vperp = v2 - dot(v2, r) * r;
    const float lperp = length(vperp);
    u = lperp > 1e-3 * length(u2) ? vperp / (lperp + eps) : vec2(-r.y, r.x);
}

// On a closed, opaque body a splat whose normal points away from the eye lies on the far side,
// hidden by the near one: drawing it costs fill for nothing. The threshold is below zero so
// the splats just past the silhouette, whose discs still reach beyond the rim, stay.
bool splat_faces_away(vec3 world, vec3 normal) {
    return dot(normal, normalize(frame.camera_pos.xyz - world)) < frame.visibility.y;
}

// The projected covariance of a full 3D Gaussian (EWA: J W Sigma W^T J^T), in view-plane units
// at the centre's depth: each world axis turned into view space (W) and pushed through the
// perspective Jacobian at the centre (a' = a.xy + p a.z), M = sum a' a'^T. Its principal axes
// (r, u) and their standard deviations (lr, lu). Like 3D Gaussian splatting, a 0.3-pixel^2
// low-pass keeps a Gaussian seen edge-on at least about a pixel wide (the paper's disc: below).
void projected_axes(vec3 c0, mat3 axes, out vec2 r, out vec2 u, out float lr, out float lu) {
    const mat3 rv = mat3(frame.view);
    const vec2 p = c0.xy / max(-c0.z, 1e-6);
    float m00 = 0.0, m01 = 0.0, m11 = 0.0;
    for (int k = 0; k < 3; ++k) {
        const vec3 a = rv * axes[k];
        const vec2 ap = a.xy + p * a.z;
        m00 += ap.x * ap.x;
        m01 += ap.x * ap.y;
        m11 += ap.y * ap.y;
    }
    const float pixel = 2.0 * max(-c0.z, 1e-6) / (abs(frame.proj[1][1]) * frame.viewport.y);
    const bool paper = k_footprint == SPLAT_FOOTPRINT_PAPER;
    if (!paper) {
        m00 += 0.3 * pixel * pixel;
        m11 += 0.3 * pixel * pixel;
    }
    const float half_diff = 0.5 * (m00 - m11);
    const float root = sqrt(half_diff * half_diff + m01 * m01);
    const float l1 = 0.5 * (m00 + m11) + root, l2 = max(0.5 * (m00 + m11) - root, 0.0);
    r = root > 1e-6 * l1 ? normalize(half_diff >= 0.0 ? vec2(l1 - m11, m01) : vec2(m01, l1 - m00)) : vec2(1.0, 0.0);
    u = vec2(-r.y, r.x);
    lr = sqrt(l1);
    lu = sqrt(l2);
    // The paper's disc is hard-edged: a smoothing filter would only fatten it (a disc under a
    // pixel would grow to one and spill past the silhouette). Seen edge-on it keeps a line a
    // pixel wide (half-size kappa * lu of half a pixel), never wider than the disc is long.
    if (paper) lu = max(lu, min(lr, 0.5 * pixel / max(frame.splat.x, 1e-6)));
}

// A surfel's axes: the Gaussian flattened onto its tangent plane, `thickness` as thick along
// the normal as it is wide. Seen edge-on at a silhouette or a fold it projects to a sliver, not
// a round disc reaching past the rim over the surface behind, shaded for the side the eye does
// not see (the dark specks).
mat3 surfel_axes(vec3 normal, float s0, float thickness) {
    const vec3 n = normalize(normal);
    vec3 t1, t2;
    splat_tangent_frame(n, t1, t2);
    return mat3(s0 * t1, s0 * t2, thickness * s0 * n);
}

// Splats under frame.material.z pixels of standard deviation (render.thin_below) are drawn
// fewer and larger: a fraction p = (sigma / target)^2 of them, by their place in the thinning
// order (surface/thin_order.h: those of each level and above cover the surface evenly), each
// grown by 1 / sqrt(p) so that together they cover what all did. On pixel-sized splats most of
// the pass is making and testing their tiny triangles' fragments, which this divides by 1 / p.
// With t = log2(1 / p), the levels below floor(t) are gone and the one at it goes splat by
// splat in rank order as t passes through it, so the count falls with p and nothing pops as a
// whole. False: not drawn.
bool splat_thin(vec3 world, vec2 place, inout float s0) {
    const float target = frame.material.z;
    if (!(target > 0.0) || k_anisotropic) return true;
    const float depth = -(frame.view * vec4(world, 1.0)).z;
    const float pixel = 2.0 * max(depth, 1e-6) / (abs(frame.proj[1][1]) * frame.viewport.y);
    const float sigma = s0 / pixel;
    if (!(sigma < target)) return true;
    // At most an eighth of them: grown further, their reach left holes (1 % of bunny_cut at the
    // checks' 240x135, splats a third of a pixel wide). The top level is never dropped.
    const float t = min(2.0 * log2(target / max(sigma, 1e-3)), float(SPLAT_THIN_LEVELS - 1));
    const float k = floor(t);
    if (place.x < k || (place.x < k + 1.0 && place.y < t - k)) return false;
    s0 *= exp2(0.5 * t);
    return true;
}

// `index`: the splat's place in the draw, where its shape is read (anisotropic pipelines).
SplatQuad splat_quad(vec3 world, vec3 normal, float s0, float alpha, bool visibility_pass, uint index) {
    SplatQuad q;
    const bool drawn = s0 > 0.0 && !splat_faces_away(world, normal);
    const float reach = drawn ? splat_reach(alpha, visibility_pass) : 0.0;
    const vec3 c0 = (frame.view * vec4(world, 1.0)).xyz;  // eq. 15
    q.centre = c0;
    if (visibility_pass) q.centre.z -= frame.visibility.x * s0;  // the camera looks down -z
    q.extent = k_footprint == SPLAT_FOOTPRINT_PAPER ? (reach > 0.0 ? 1.0 : 0.0) : reach;
    q.plane = !k_anisotropic && frame.material.y > 0.0 ? mat3(frame.view) * normalize(normal) : vec3(0.0);
    if (k_anisotropic || frame.material.y > 0.0) {
        vec2 r, u;
        float lr, lu;
        projected_axes(c0, k_anisotropic ? read_shape_axes(index) : surfel_axes(normal, s0, frame.material.y), r, u, lr, lu);
        q.axis_right = reach * lr * vec3(r, 0.0);
        q.axis_up = reach * lu * vec3(u, 0.0);
        return q;
    }

    // Eqs. 19-20 take the lengths of the view-plane axes alone, which is exact only where the
    // view ray through the centre is the optical axis. Off axis a sphere projects to an ellipse
    // stretched away from the image centre: mapping each axis through the perspective Jacobian
    // at the centre (in view-plane units at the centre's depth: a' = a.xy + p a.z, with
    // p = c.xy / -c.z), the projected covariance is M = sum a' a'^T = s0^2 (I + p p^T) for an
    // isotropic Gaussian (the axes are the rows of a rotation). Its principal axes are p, with
    // length s0 sqrt(1 + |p|^2), and the perpendicular, with length s0: the carrier bounds the
    // projected Gaussian at the cut-off and the fragment stage's axis-aligned ellipse is that
    // projection. On the axis (p = 0) M is isotropic and the paper's frame (eqs. 16-18) stays;
    // it is only computed where the sharpness makes the orientation visible.
    const vec2 p = c0.xy / max(-c0.z, 1e-6);
    const float p2 = dot(p, p);
    vec2 r, u;
    if (p2 > 1e-8) {
        r = p * inversesqrt(p2);
        u = vec2(-r.y, r.x);
    } else if (frame.splat.y != frame.splat.z) {
        paper_frame(c0, s0, r, u);
    } else {
        r = vec2(1.0, 0.0);
        u = vec2(0.0, 1.0);
    }
    const float lr = s0 * sqrt(1.0 + p2), lu = s0;
    // The Gaussian's uv is in standard deviations (the carrier spans its reach); the paper's is
    // the quad's own [-1,1] (eq. 22 divides it by the sharpness).
    q.axis_right = reach * lr * vec3(r, 0.0);
    q.axis_up = reach * lu * vec3(u, 0.0);
    return q;
}

// Corner i of the carrier (strip order): clip position, world position, uv, and the distance
// along the view axis at which the view ray through the corner meets the splat's surface (its
// plane for a surfel, the centre's depth otherwise; mesh occluders compare it with the surface's
// own). A carrier with nothing to draw lands outside the clip volume.
void splat_corner(SplatQuad q, vec3 world, int i, out vec4 clip, out vec3 corner_world, out vec2 uv, out float depth) {
    const vec2 c = carrier_corner(i);
    const vec3 offset = c.x * q.axis_right + c.y * q.axis_up;
    clip = q.extent > 0.0 ? frame.proj * vec4(q.centre + offset, 1.0) : vec4(2.0, 2.0, 2.0, 1.0);
    corner_world = world + transpose(mat3(frame.view)) * offset;
    uv = c * q.extent;
    const vec3 c0 = (frame.view * vec4(world, 1.0)).xyz;
    depth = -c0.z;
    if (q.plane != vec3(0.0)) {
        // The ray t (c0 + offset) meets the plane at t = n.c0 / n.(c0 + offset). Seen at a grazing
        // angle that is far out: the surface then lies within about the carrier's size in depth.
        const float along = dot(q.plane, c0 + offset);
        const float slack = 2.0 * max(length(q.axis_right), length(q.axis_up));
        const float t = abs(along) > 1e-12 ? dot(q.plane, c0) / along : 1.0;
        depth = clamp(t * depth, depth - slack, depth + slack);
    }
}

#endif
