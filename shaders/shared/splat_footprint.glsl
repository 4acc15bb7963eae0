// The screen-space footprint of one isotropic Gaussian (paper section 5.5), shared by the
// geometry-shader, mesh-shader and vertex-pulling paths so the three draw the same quads.
// Needs `frame` (FrameUniforms) declared before inclusion.
#ifndef PBDSPLAT_SPLAT_FOOTPRINT_GLSL
#define PBDSPLAT_SPLAT_FOOTPRINT_GLSL

#include "splat_codec.glsl"

struct SplatQuad {
    vec3 centre;      // view space (eq. 15), pushed back in the visibility pass
    vec3 axis_right;  // view space, kappa * l_r along r (eq. 19)
    vec3 axis_up;     // view space, kappa * l_u along u_perp (eq. 20)
    float extent;     // the quad covers uv in [-extent, extent]^2
};

const vec2 k_quad_corners[4] = vec2[4](vec2(-1.0, -1.0), vec2(1.0, -1.0), vec2(-1.0, 1.0), vec2(1.0, 1.0));

SplatQuad splat_quad(vec3 world, float s0, bool visibility_pass) {
    // Eq. 14 with S_local = s0*I, R_local = R_model = I: the local axes seen in view space are
    // the columns of the view rotation, scaled.
    const mat3 rv = mat3(frame.view);
    const vec3 a[3] = vec3[3](s0 * rv[0], s0 * rv[1], s0 * rv[2]);
    const vec3 c0 = (frame.view * vec4(world, 1.0)).xyz;  // eq. 15
    SplatQuad q;
    q.centre = c0;
    if (visibility_pass) q.centre.z -= frame.visibility.x * s0;  // the camera looks down -z

    // Eq. 16: view-plane contribution of each axis; drop the weakest.
    const float ck[3] = float[3](dot(a[0].xy, a[0].xy), dot(a[1].xy, a[1].xy), dot(a[2].xy, a[2].xy));
    int weakest = 0;
    if (ck[1] < ck[weakest]) weakest = 1;
    if (ck[2] < ck[weakest]) weakest = 2;
    const int iu = ck[(weakest + 1) % 3] >= ck[(weakest + 2) % 3] ? (weakest + 1) % 3 : (weakest + 2) % 3;
    const int iv = 3 - weakest - iu;

    // Eqs. 17-18: 2D Gram-Schmidt, with a perpendicular fallback when v collapses onto u.
    const float eps = 1e-6;
    const vec2 u2 = a[iu].xy;
    const vec2 r2 = u2 / (length(u2) + eps);
    const vec2 v2 = a[iv].xy;
    const vec2 vperp = v2 - dot(v2, r2) * r2;
    const float lperp = length(vperp);
    const vec2 up2 = lperp > 1e-3 * length(u2) ? vperp / (lperp + eps) : vec2(-r2.y, r2.x);

    // Eqs. 19-20 take the lengths of u and v_perp alone, which is exact only where the view ray
    // through the centre is the optical axis. Off axis a sphere projects to an ellipse stretched
    // away from the image centre, so we map each axis through the perspective Jacobian at the
    // centre (in view-plane units at the centre's depth: a' = a.xy + p a.z, p = c.xy / -c.z),
    // and turn the Gram-Schmidt frame onto the principal axes of the projected covariance
    // M = sum a' a'^T: the quad then bounds the projected Gaussian at the cut-off and the
    // fragment stage's axis-aligned ellipse is that projection. Where M is isotropic (on the
    // axis) the paper's frame stays.
    const vec2 p = c0.xy / max(-c0.z, 1e-6);
    float m00 = 0.0, m01 = 0.0, m11 = 0.0;
    for (int k = 0; k < 3; ++k) {
        const vec2 ap = a[k].xy + p * a[k].z;
        m00 += ap.x * ap.x;
        m01 += ap.x * ap.y;
        m11 += ap.y * ap.y;
    }
    const float half_diff = 0.5 * (m00 - m11);
    const float root = sqrt(half_diff * half_diff + m01 * m01);
    const float l1 = 0.5 * (m00 + m11) + root, l2 = max(0.5 * (m00 + m11) - root, 0.0);
    vec2 r = r2, u = up2;
    if (root > 1e-4 * l1) {
        r = normalize(half_diff >= 0.0 ? vec2(l1 - m11, m01) : vec2(m01, l1 - m00));
        u = vec2(-r.y, r.x);
    }
    const float lr = sqrt(l1), lu = sqrt(l2);
    // The visibility pass only needs the core that writes depth: a smaller quad, less fill.
    q.extent = visibility_pass ? sqrt(frame.visibility.y) : 1.0;
    const float kappa = frame.splat.x * q.extent;
    q.axis_right = kappa * lr * vec3(r, 0.0);
    q.axis_up = kappa * lu * vec3(u, 0.0);
    return q;
}

// Corner i (0..3, triangle-strip order) of the quad: clip position and world position.
void splat_corner(SplatQuad q, vec3 world, int i, out vec4 clip, out vec3 corner_world, out vec2 uv) {
    const vec3 offset = k_quad_corners[i].x * q.axis_right + k_quad_corners[i].y * q.axis_up;
    clip = frame.proj * vec4(q.centre + offset, 1.0);
    corner_world = world + transpose(mat3(frame.view)) * offset;
    uv = k_quad_corners[i] * q.extent;
}

#endif
