#version 460
// Splat pass, geometry stage: expands one isotropic Gaussian into a view-plane quad
// (paper section 5.5). The quad is only a carrier; the fragment stage masks the ellipse.
#include "gpu_types.h"

layout(points) in;
layout(triangle_strip, max_vertices = 4) out;

layout(set = 0, binding = 0, std140) uniform Frame { FrameUniforms frame; };

// The visibility pass pushes every quad back along the view ray, so splats of the front surface
// later blend over one another while the hidden surfaces behind stay rejected.
layout(constant_id = 0) const bool k_visibility_pass = false;

layout(location = 0) in vec3 v_normal[];
layout(location = 1) in vec4 v_color[];
layout(location = 2) in vec2 v_scale_opacity[];

layout(location = 0) out vec2 g_uv;         // [-1,1]^2 across the quad
layout(location = 1) out vec3 g_world;      // world position of the fragment (for env lookups)
layout(location = 2) out vec3 g_normal;
layout(location = 3) out vec4 g_color;      // rgb albedo, a = fade
layout(location = 4) out float g_opacity;   // sigmoid(o), eq. 21

const float k_eps = 1e-6;

void main() {
    const vec3 world = gl_in[0].gl_Position.xyz;
    const float s0 = v_scale_opacity[0].x * frame.splat.w;
    if (!(s0 > 0.0)) return;  // a zero or NaN scale draws nothing rather than garbage

    // Eq. 14 with S_local = s0*I, R_local = R_model = I: the local axes seen in view space are
    // the columns of the view rotation, scaled.
    const mat3 rv = mat3(frame.view);
    const vec3 a[3] = vec3[3](s0 * rv[0], s0 * rv[1], s0 * rv[2]);
    vec3 c = (frame.view * vec4(world, 1.0)).xyz;  // eq. 15
    if (k_visibility_pass) c.z -= frame.visibility.x * s0;  // the camera looks down -z

    // Eq. 16: view-plane contribution of each axis; drop the weakest.
    const float ck[3] = float[3](dot(a[0].xy, a[0].xy), dot(a[1].xy, a[1].xy), dot(a[2].xy, a[2].xy));
    int weakest = 0;
    if (ck[1] < ck[weakest]) weakest = 1;
    if (ck[2] < ck[weakest]) weakest = 2;
    const int iu = ck[(weakest + 1) % 3] >= ck[(weakest + 2) % 3] ? (weakest + 1) % 3 : (weakest + 2) % 3;
    const int iv = 3 - weakest - iu;

    // Eqs. 17-18: 2D Gram-Schmidt, with a perpendicular fallback when v collapses onto u.
    const vec2 u2 = a[iu].xy;
    const vec2 r2 = u2 / (length(u2) + k_eps);
    const vec2 v2 = a[iv].xy;
    const vec2 vperp = v2 - dot(v2, r2) * r2;
    const float lperp = length(vperp);
    const vec2 up2 = lperp > 1e-3 * length(u2) ? vperp / (lperp + k_eps) : vec2(-r2.y, r2.x);

    // Eqs. 19-20 take the lengths of u and v_perp alone; with an isotropic Gaussian the dropped
    // axis still projects onto the plane, so we take the footprint's full extent along r2 and
    // up2 (the square root of the projected covariance), which reduces to eq. 19 when the
    // dropped axis is parallel to the view direction.
    float lr = 0.0, lu = 0.0;
    for (int k = 0; k < 3; ++k) {
        lr += dot(a[k].xy, r2) * dot(a[k].xy, r2);
        lu += dot(a[k].xy, up2) * dot(a[k].xy, up2);
    }
    lr = sqrt(lr);
    lu = sqrt(lu);
    // The visibility pass only needs the core that writes depth: a smaller quad, less fill.
    const float extent = k_visibility_pass ? sqrt(frame.visibility.y) : 1.0;
    const float kappa = frame.splat.x * extent;
    const vec3 axis_right = kappa * lr * vec3(r2, 0.0);
    const vec3 axis_up = kappa * lu * vec3(up2, 0.0);
    const mat3 view_to_world = transpose(rv);

    const vec2 corners[4] = vec2[4](vec2(-1.0, -1.0), vec2(1.0, -1.0), vec2(-1.0, 1.0), vec2(1.0, 1.0));
    for (int i = 0; i < 4; ++i) {
        const vec3 offset = corners[i].x * axis_right + corners[i].y * axis_up;
        gl_Position = frame.proj * vec4(c + offset, 1.0);
        g_uv = corners[i] * extent;
        g_world = world + view_to_world * offset;
        g_normal = v_normal[0];
        g_color = v_color[0];
        g_opacity = 1.0 / (1.0 + exp(-v_scale_opacity[0].y));
        EmitVertex();
    }
    EndPrimitive();
}
