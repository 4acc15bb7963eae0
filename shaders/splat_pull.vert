#version 460
// Splat pass, vertex-pulling path for devices without geometry shaders: six vertices per
// Gaussian (two triangles, the same diagonal as the geometry shader's strip), the record read
// from a storage buffer by gl_VertexIndex / 6.
#include "gpu_types.h"

layout(set = 0, binding = 0, std140) uniform Frame { FrameUniforms frame; };
layout(set = 0, binding = 1) uniform sampler2D env_map;
#include "splat_footprint.glsl"
#include "shading.glsl"
#include "splat_corner.glsl"
#include "splat_record.glsl"
#include "splat_texture.glsl"

layout(constant_id = 0) const bool k_visibility_pass = false;

layout(location = 0) out vec2 g_uv;
layout(location = 1) out vec3 g_world;
layout(location = 2) out vec3 g_normal;
layout(location = 3) out vec4 g_color;
layout(location = 4) out float g_depth;  // distance to the splat's surface along the view axis
layout(location = 5) out vec3 g_tex;     // see corner_texcoord()
layout(location = 6) flat out vec3 g_tex_centre;  // see texcoord_centre()
layout(location = 7) flat out vec3 g_tex_metric;  // see texcoord_metric()
layout(location = 8) flat out uint g_model;       // whose centre the environment lookups look out from

// Strip corners (0, 1, 2) and (2, 1, 3): the quad strip's two triangles.
const int k_corner_of_vertex[6] = int[6](0, 1, 2, 2, 1, 3);

void main() {
    const SplatRecord r = read_record(uint(gl_VertexIndex) / 6u);
    float s0 = r.scale * frame.splat.w;
    const float alpha = splat_alpha(r.color.a, r.opacity_logit);
    if (!splat_thin(r.position, r.thin, s0)) s0 = 0.0;
    g_normal = r.normal;
    g_model = r.model;
    if (!(s0 > 0.0)) {  // nothing to draw: a point outside the clip volume
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
        g_uv = vec2(0.0);
        g_world = r.position;
        g_color = vec4(0.0);
        g_depth = 0.0;
        g_tex = vec3(0.0, 0.0, -1.0);
        g_tex_centre = vec3(0.0);
        g_tex_metric = vec3(0.0);
        return;
    }
    // Always the quad: six vertices per splat, each running the whole footprint, make an
    // octagon's eighteen cost more than the fill it saves.
    const SplatQuad q = splat_quad(r.position, r.normal, s0, alpha, k_visibility_pass, uint(gl_VertexIndex) / 6u);
    splat_corner(q, r.position, k_corner_of_vertex[gl_VertexIndex % 6], gl_Position, g_world, g_uv, g_depth);
    g_normal = corner_normal(r.normal, r.curvature, r.position, g_world);
    const SplatTexcoord tex = read_texcoord(uint(gl_VertexIndex) / 6u);
    g_color = corner_color(textured_albedo(tex, splat_albedo(r.color.rgb, uint(gl_VertexIndex) / 6u, r.position)), alpha, g_normal, g_world, r.model);
    g_tex = corner_texcoord(tex, r.normal, r.position, g_world);
    g_tex_centre = texcoord_centre(tex);
    g_tex_metric = texcoord_metric(tex);
}
