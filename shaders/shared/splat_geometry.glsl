// Splat pass, geometry-shader path (splat.geom, splat_occluded.geom): expands one isotropic Gaussian into a view-plane carrier
// (paper section 5.5). The carrier only bounds the footprint; the fragment stage masks it.
#ifndef PBDSPLAT_SPLAT_GEOMETRY_GLSL
#define PBDSPLAT_SPLAT_GEOMETRY_GLSL

#include "gpu_types.h"

layout(points) in;
layout(triangle_strip, max_vertices = 8) out;

layout(set = 0, binding = 0, std140) uniform Frame { FrameUniforms frame; };
layout(set = 0, binding = 1) uniform sampler2D env_map;
#include "splat_footprint.glsl"
#include "shading.glsl"
#include "splat_corner.glsl"
#include "splat_texture.glsl"
#ifdef PBDSPLAT_OCCLUDERS
#include "splat_occluder_cull.glsl"
#endif

// The visibility pass pushes every carrier back along the view ray, so splats of the front
// surface later blend over one another while the hidden surfaces behind stay rejected.
layout(constant_id = 0) const bool k_visibility_pass = false;

layout(location = 0) in vec3 v_normal[];
layout(location = 1) in vec4 v_color[];
layout(location = 2) in vec2 v_scale_opacity[];
layout(location = 3) in mat3 v_curvature[];
layout(location = 6) in vec2 v_thin[];
layout(location = 7) flat in uint v_model[];

layout(location = 0) out vec2 g_uv;         // see splat_quad(): std devs, or the paper's [-1,1]
layout(location = 1) out vec3 g_world;      // world position of the fragment (for env lookups)
layout(location = 2) out vec3 g_normal;
layout(location = 3) out vec4 g_color;      // see corner_color()
layout(location = 4) out float g_depth;  // distance to the splat's surface along the view axis
layout(location = 5) out vec3 g_tex;     // see corner_texcoord()
layout(location = 6) flat out vec3 g_tex_centre;  // see texcoord_centre()
layout(location = 7) flat out vec3 g_tex_metric;  // see texcoord_metric()
layout(location = 8) flat out uint g_model;       // whose centre the environment lookups look out from

void main() {
    const vec3 world = gl_in[0].gl_Position.xyz;
    float s0 = v_scale_opacity[0].x * frame.splat.w;
    if (!(s0 > 0.0)) return;  // a zero or NaN scale draws nothing rather than garbage
    if (splat_faces_away(world, v_normal[0])) return;  // the far side of a closed body
    const float alpha = splat_alpha(v_color[0].a, v_scale_opacity[0].y);
    if (!splat_thin(world, v_thin[0], s0)) return;
    const SplatQuad q = splat_quad(world, v_normal[0], s0, alpha, k_visibility_pass, uint(gl_PrimitiveIDIn));
    if (!(q.extent > 0.0)) return;  // too faint to show anywhere
    const SplatTexcoord tex = read_texcoord(uint(gl_PrimitiveIDIn));
#ifdef PBDSPLAT_OCCLUDERS
    if (splat_hidden(q, world)) return;
#endif
    const vec3 albedo = textured_albedo(tex, splat_albedo(v_color[0].rgb, uint(gl_PrimitiveIDIn), world));
    for (int i = 0; i < k_carrier_corners; ++i) {
        splat_corner(q, world, i, gl_Position, g_world, g_uv, g_depth);
        g_normal = corner_normal(v_normal[0], v_curvature[0], world, g_world);
        g_color = corner_color(albedo, alpha, g_normal, g_world, v_model[0]);
        g_tex = corner_texcoord(tex, v_normal[0], world, g_world);
        g_tex_centre = texcoord_centre(tex);
        g_tex_metric = texcoord_metric(tex);
        g_model = v_model[0];
        EmitVertex();
    }
    EndPrimitive();
}

#endif
