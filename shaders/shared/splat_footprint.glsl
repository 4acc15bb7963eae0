// The screen-space footprint of one isotropic Gaussian (paper section 5.5), shared by the
// geometry-shader, mesh-shader and vertex-pulling paths so the three draw the same quads.
// Needs `frame` (FrameUniforms) declared before inclusion.
#ifndef PBDSPLAT_SPLAT_FOOTPRINT_GLSL
#define PBDSPLAT_SPLAT_FOOTPRINT_GLSL

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
    SplatQuad q;
    q.centre = (frame.view * vec4(world, 1.0)).xyz;
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

    // Eqs. 19-20 take the lengths of u and v_perp alone; with an isotropic Gaussian the dropped
    // axis still projects onto the plane, so we take the footprint's full extent along r2 and
    // up2 (the square root of the projected covariance), which reduces to eq. 19 when the
    // dropped axis is parallel to the view direction.
    float lr = 0.0, lu = 0.0;
    for (int k = 0; k < 3; ++k) {
        lr += dot(a[k].xy, r2) * dot(a[k].xy, r2);
        lu += dot(a[k].xy, up2) * dot(a[k].xy, up2);
    }
    // The visibility pass only needs the core that writes depth: a smaller quad, less fill.
    q.extent = visibility_pass ? sqrt(frame.visibility.y) : 1.0;
    const float kappa = frame.splat.x * q.extent;
    q.axis_right = kappa * sqrt(lr) * vec3(r2, 0.0);
    q.axis_up = kappa * sqrt(lu) * vec3(up2, 0.0);
    return q;
}

// Corner i (0..3, triangle-strip order) of the quad: clip position and world position.
void splat_corner(SplatQuad q, vec3 world, int i, out vec4 clip, out vec3 corner_world, out vec2 uv) {
    const vec3 offset = k_quad_corners[i].x * q.axis_right + k_quad_corners[i].y * q.axis_up;
    clip = frame.proj * vec4(q.centre + offset, 1.0);
    corner_world = world + transpose(mat3(frame.view)) * offset;
    uv = k_quad_corners[i] * q.extent;
}

vec3 decode_octahedral(vec2 e) {
    vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
    if (n.z < 0.0) n.xy = (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
    return normalize(n);
}

float sigmoid(float o) { return 1.0 / (1.0 + exp(-o)); }

#endif
