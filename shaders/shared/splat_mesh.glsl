// Splat pass, mesh-shader path (VK_EXT_mesh_shader; splat.mesh, splat_occluded.mesh): each
// workgroup turns a fixed number of Gaussians into carriers (quads of two triangles, or octagons
// of six), with no geometry stage.
#ifndef PBDSPLAT_SPLAT_MESH_GLSL
#define PBDSPLAT_SPLAT_MESH_GLSL

#extension GL_EXT_mesh_shader : require
#include "gpu_types.h"

#define SPLATS_PER_GROUP 32
layout(local_size_x = SPLATS_PER_GROUP) in;
layout(triangles, max_vertices = 8 * SPLATS_PER_GROUP, max_primitives = 6 * SPLATS_PER_GROUP) out;

layout(set = 0, binding = 0, std140) uniform Frame { FrameUniforms frame; };
layout(set = 0, binding = 1) uniform sampler2D env_map;
#include "splat_footprint.glsl"
#include "shading.glsl"
#include "splat_corner.glsl"
#include "splat_record.glsl"
#include "splat_texture.glsl"
#ifdef PBDSPLAT_OCCLUDERS
#include "splat_occluder_cull.glsl"
#endif

layout(constant_id = 0) const bool k_visibility_pass = false;
layout(push_constant) uniform Push { uint count; } push;

layout(location = 0) out vec2 g_uv[];
layout(location = 1) out vec3 g_world[];
layout(location = 2) out vec3 g_normal[];
layout(location = 3) out vec4 g_color[];
layout(location = 4) out float g_depth[];  // distance to the splat's surface along the view axis
layout(location = 5) out vec3 g_tex[];     // see corner_texcoord()
layout(location = 6) flat out vec3 g_tex_centre[];  // see texcoord_centre()
layout(location = 7) flat out vec3 g_tex_metric[];  // see texcoord_metric()
layout(location = 8) flat out uint g_model[];       // whose centre the environment lookups look out from

void main() {
    const uint first = gl_WorkGroupID.x * SPLATS_PER_GROUP;
    const uint n = min(uint(SPLATS_PER_GROUP), push.count - first);
    const uint nv = uint(k_carrier_corners), nt = nv - 2u;
    SetMeshOutputsEXT(nv * n, nt * n);
    const uint k = gl_LocalInvocationIndex;
    if (k >= n) return;
    const SplatRecord r = read_record(first + k);
    float s0 = r.scale * frame.splat.w;
    // A zero or NaN scale, or a splat too faint to show or thinned out, gets an empty carrier
    // whose corners all lie outside the clip volume (gl_CullPrimitiveEXT would pull the
    // shading-rate capability into the module).
    const float alpha = splat_alpha(r.color.a, r.opacity_logit);
    if (!splat_thin(r.position, r.thin, s0)) s0 = 0.0;
    SplatQuad q = splat_quad(r.position, r.normal, s0 > 0.0 ? s0 : 0.0, alpha, k_visibility_pass, first + k);
#ifdef PBDSPLAT_OCCLUDERS
    if (q.extent > 0.0 && splat_hidden(q, r.position)) q.extent = 0.0;  // empty, as above
#endif
    const SplatTexcoord tex = read_texcoord(first + k);
    const vec3 albedo = textured_albedo(tex, splat_albedo(r.color.rgb, first + k, r.position));
    for (uint i = 0; i < nv; ++i) {
        const uint v = nv * k + i;
        vec4 clip;
        splat_corner(q, r.position, int(i), clip, g_world[v], g_uv[v], g_depth[v]);
        gl_MeshVerticesEXT[v].gl_Position = clip;
        g_normal[v] = corner_normal(r.normal, r.curvature, r.position, g_world[v]);
        g_color[v] = corner_color(albedo, alpha, g_normal[v], g_world[v], r.model);
        g_tex[v] = corner_texcoord(tex, r.normal, r.position, g_world[v]);
        g_tex_centre[v] = texcoord_centre(tex);
        g_tex_metric[v] = texcoord_metric(tex);
        g_model[v] = r.model;
    }
    // The strip as a triangle list, every other triangle flipped to keep one winding.
    for (uint j = 0; j < nt; ++j) {
        const uint b = nv * k + j;
        gl_PrimitiveTriangleIndicesEXT[nt * k + j] = (j & 1u) == 0u ? uvec3(b, b + 1u, b + 2u) : uvec3(b + 1u, b, b + 2u);
    }
}

#endif
