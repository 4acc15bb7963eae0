// Splat pass, fragment stage: the footprint's mask (paper section 5.6.1) and shading
// (section 5.6.2), with premultiplied alpha for the "over" blend. Included by splat.frag (the
// pipelines that test depth without writing it), splat_paper.frag (the paper's one pass,
// which writes depth and so cannot test early) and splat_accumulate.frag (normalised blending's
// weighted sums).
#ifndef PBDSPLAT_SPLAT_FRAGMENT_GLSL
#define PBDSPLAT_SPLAT_FRAGMENT_GLSL

#include "gpu_types.h"

layout(set = 0, binding = 0, std140) uniform Frame { FrameUniforms frame; };
layout(set = 0, binding = 1) uniform sampler2D env_map;
#include "shading.glsl"

layout(constant_id = 1) const bool k_shade_per_corner = false;
layout(constant_id = 2) const uint k_footprint = SPLAT_FOOTPRINT_GAUSSIAN;
const float k_alpha_floor = 1.0 / 255.0;
// The paper footprint's opacity as dithered coverage (its depth-writing pass) or as blending
// (its additive pass, where order does not matter).
layout(constant_id = 4) const bool k_footprint_dither = false;
// The splats stand for an opaque surface as the paper's disc does (normalised blending): see
// splat_lit_normal in shading.glsl.
layout(constant_id = 7) const bool k_opaque_surface = false;

layout(location = 0) in vec2 g_uv;
layout(location = 1) in vec3 g_world;
layout(location = 2) in vec3 g_normal;
layout(location = 3) in vec4 g_color;  // rgb: albedo, or the colour shaded at the corners; a: opacity
// A textured splat's texture coordinates and texture (splat_texture.glsl; z < 0: none).
layout(location = 5) in vec3 g_tex;
// The centre's coordinates, how far from the centre the splat may read (short of a seam), and
// the metric of the coordinates along the surface (texcoord_centre(), texcoord_metric()).
layout(location = 6) flat in vec3 g_tex_centre;
layout(location = 7) flat in vec3 g_tex_metric;
layout(location = 8) flat in uint g_model;
layout(constant_id = 8) const uint k_texture_count = 0u;  // as in splat_texture.glsl
const bool k_textured = k_texture_count > 0u;
layout(set = 0, binding = 7) uniform sampler2D splat_textures[SPLAT_MAX_TEXTURES];

layout(location = 0) out vec4 out_color;
#ifdef PBDSPLAT_OCCLUDERS
// The surface mesh's own distance along the view axis at this pixel (render/occluder_pass.h;
// 0 where no surface is), and the splat's from splat_corner().
layout(location = 4) in float g_depth;
layout(set = 1, binding = 0) uniform sampler2D occluder_depth;
#endif
#ifdef PBDSPLAT_WEIGHTED_OUTPUT
layout(location = 1) out vec4 out_inside;  // normalised blending's second layer (normalised_blend.h)
#endif

// A 4x4 ordered-dither threshold in (0, 1) for this pixel.
float dither_threshold() {
    const uint bayer[16] = uint[16](0u, 8u, 2u, 10u, 12u, 4u, 14u, 6u, 3u, 11u, 1u, 9u, 15u, 7u, 13u, 5u);
    const uvec2 p = uvec2(gl_FragCoord.xy) & 3u;
    return (float(bayer[p.y * 4u + p.x]) + 0.5) / 16.0;
}

// Texture `which` of the k_texture_count: each read names its array entry with a constant, so no
// device feature for non-uniform indexing is needed, and the specialised count leaves only the
// reads of the textures there are (one, for most models).
vec3 texture_at(int which, vec2 uv) {
    if (k_texture_count <= 1u || which <= 0) return textureLod(splat_textures[0], uv, 0.0).rgb;
    if (k_texture_count <= 2u || which == 1) return textureLod(splat_textures[1], uv, 0.0).rgb;
    if (k_texture_count <= 3u || which == 2) return textureLod(splat_textures[2], uv, 0.0).rgb;
    if (k_texture_count <= 4u || which == 3) return textureLod(splat_textures[3], uv, 0.0).rgb;
    if (k_texture_count <= 5u || which == 4) return textureLod(splat_textures[4], uv, 0.0).rgb;
    if (k_texture_count <= 6u || which == 5) return textureLod(splat_textures[5], uv, 0.0).rgb;
    if (k_texture_count <= 7u || which == 6) return textureLod(splat_textures[6], uv, 0.0).rgb;
    return textureLod(splat_textures[7], uv, 0.0).rgb;
}

ivec2 texture_extent(int which) {
    if (k_texture_count <= 1u || which <= 0) return textureSize(splat_textures[0], 0);
    if (k_texture_count <= 2u || which == 1) return textureSize(splat_textures[1], 0);
    if (k_texture_count <= 3u || which == 2) return textureSize(splat_textures[2], 0);
    if (k_texture_count <= 4u || which == 3) return textureSize(splat_textures[3], 0);
    if (k_texture_count <= 5u || which == 4) return textureSize(splat_textures[4], 0);
    if (k_texture_count <= 6u || which == 5) return textureSize(splat_textures[5], 0);
    if (k_texture_count <= 7u || which == 6) return textureSize(splat_textures[6], 0);
    return textureSize(splat_textures[7], 0);
}

// The texture over this pixel, white for an untextured splat: near its mean over the pixel's
// square, as a surface drawn with many samples a pixel shows it (a texture's edge inside a
// pixel drawn as the part of it on each side). One read where the texture is magnified enough
// that the bilinear read is that mean already, else four on a rotated grid. (Sixteen where a
// pixel covers more than 1.5 texels, towards the silhouette, lowered a globe's colour error by
// 2 % for 8 % more of the frame on Lavapipe; sixteen everywhere by 7 % for two thirds more.)
// The explicit level reads the full-size image as the mesh raster does. `dx`, `dy`: the
// coordinates' change per pixel, taken before anything discards.
vec3 texel(vec2 dx, vec2 dy) {
    if (!k_textured || g_tex.z < 0.0) return vec3(1.0);
    const int which = int(g_tex.z + 0.5);
    // Past the reach the read stays at its rim, as a clamped texture does at its edge.
    vec2 uv = g_tex.xy;
    const vec2 off = uv - g_tex_centre.xy;
    const float far2 = off.x * (g_tex_metric.x * off.x + g_tex_metric.y * off.y) + off.y * (g_tex_metric.y * off.x + g_tex_metric.z * off.y);
    if (far2 > g_tex_centre.z * g_tex_centre.z) uv = g_tex_centre.xy + off * (g_tex_centre.z * inversesqrt(far2));
    const vec2 size = vec2(texture_extent(which));
    if (max(length(dx * size), length(dy * size)) < 0.35) return texture_at(which, uv);
    const vec2 a = 0.125 * dx + 0.375 * dy, b = 0.375 * dx - 0.125 * dy;
    return 0.25 * (texture_at(which, uv + a) + texture_at(which, uv - a) + texture_at(which, uv + b) + texture_at(which, uv - b));
}

void main() {
    const vec2 tex_dx = k_textured ? dFdx(g_tex.xy) : vec2(0.0), tex_dy = k_textured ? dFdy(g_tex.xy) : vec2(0.0);
#ifdef PBDSPLAT_OCCLUDERS
    // Only the surface the mesh shows at this pixel: a splat reaching past an occluding contour
    // (a head over the ear behind it, a crease's near face over the far one) lies well in front
    // of it there and would paint that surface over with its own colour. Past the body's outline
    // (no surface) a splat keeps a pixel of its soft rim, no more: the outline is the surface's,
    // drawn smooth. In front the tolerance is doubled: a contour's splats lie far in front of
    // what they reach over, while a folded cut face's splats, each on its own triangle's plane,
    // pass over a neighbour folding away from the eye just in front of it: at the tolerance alone
    // the pixels only such rims reached were left empty (pinholes down bunny_cut's faces).
    // Behind, the surfaces a tolerance as wide would let through raise the shading error.
    const ivec2 pixel = ivec2(gl_FragCoord.xy);
    const float surface = texelFetch(occluder_depth, pixel, 0).r;
    if (surface > 0.0) {
        const float off = g_depth - surface;  // > 0: behind the surface
        // A splat facing away from the eye behind the surface shown is the far side of a part
        // thinner than the tolerance (a plate, a leaf): averaged in, its down-facing splats
        // mottled a 1 cm plate's top dark. On the seen surface itself (an opened body's inside,
        // a silhouette's rim) it lies on the mesh, far within a tenth of the tolerance.
        const bool away = dot(g_normal, frame.camera_pos.xyz - g_world) < 0.0;
        if (off > (away ? 0.1 : 1.0) * frame.visibility.w || off < -2.0 * frame.visibility.w) discard;
    } else {
        const ivec2 last = textureSize(occluder_depth, 0) - 1;
        const float near = max(max(texelFetch(occluder_depth, min(pixel + ivec2(1, 0), last), 0).r,
                                   texelFetch(occluder_depth, max(pixel - ivec2(1, 0), ivec2(0)), 0).r),
                               max(texelFetch(occluder_depth, min(pixel + ivec2(0, 1), last), 0).r,
                                   texelFetch(occluder_depth, max(pixel - ivec2(0, 1), ivec2(0)), 0).r));
        if (!(near > 0.0)) discard;
    }
#endif
    // Eqs. 22-23: normalise by the sharpness.
    const vec2 u = g_uv / frame.splat.yz;
    const float r2 = dot(u, u);
    float alpha;
    if (k_footprint == SPLAT_FOOTPRINT_PAPER) {
        if (r2 > 1.0) discard;  // outside the unit ellipse
        // Eq. 21's flat alpha, drawn as coverage: the paper blends it over whatever is already
        // drawn, which with depth writes and no sort is the draw order's accident (a disc fading
        // in after a cut would show the background through, not its neighbours: dark specks).
        // Kept on an ordered-dither share of the pixels, it has the same mean opacity whatever
        // the order, and the kept pixels write an opaque colour.
        // (Opaque discs, nearly all of them, skip the threshold: the largest is 15.5/16.)
        if (k_footprint_dither && g_color.a < 0.97 && g_color.a < dither_threshold()) discard;
        alpha = k_footprint_dither ? 1.0 : g_color.a;
    } else {
        // uv is in standard deviations: the Gaussian falloff, cut where it stops showing and,
        // with kappa set, at kappa standard deviations: a disc, whatever carrier bounds it (a
        // quad's corners reach 1.4 kappa, an octagon's 1.08 kappa).
        alpha = min(g_color.a * exp(-0.5 * r2), 1.0);
        if (alpha < k_alpha_floor) discard;
        if (frame.splat.x > 0.0 && dot(g_uv, g_uv) > frame.splat.x * frame.splat.x) discard;
    }
    const vec3 facing = normalize(g_normal);
    const vec3 n = splat_lit_normal(facing, g_world, k_footprint == SPLAT_FOOTPRINT_PAPER, k_opaque_surface);
    // Seen from behind (an open body's inside), over the same angles over which
    // splat_lit_normal turns to the seen side; the inside may have a colour of its own.
    const float behind = -dot(facing, normalize(frame.camera_pos.xyz - g_world));
    const float inside = k_opaque_surface ? smoothstep(0.15, 0.45, behind) : 0.0;
    // Shaded at the corners, the texture multiplies the shaded colour (its highlights too).
    const vec3 surface_color = g_color.rgb * texel(tex_dx, tex_dy);
    const vec3 albedo = mix(surface_color, frame.interior.rgb, frame.interior.a * inside);
    const vec3 color = k_shade_per_corner ? surface_color : shade(albedo, n, g_world, g_model);
#ifdef PBDSPLAT_WEIGHTED_OUTPUT
    // Normalised blending's weight: -ln(1 - alpha) adds up like a log transmittance (the resolve
    // recovers the coverage from the sum), and weighs each splat's colour by how much it covers,
    // falling smoothly to nothing at its rim.
    const float w = -log(1.0 - min(alpha, 0.996));
    // Seen from behind, the weight goes to the second layer (shared between the two as above).
    out_color = vec4(color, 1.0) * (w * (1.0 - inside));
    out_inside = vec4(color, 1.0) * (w * inside);
#else
    out_color = vec4(color * alpha, alpha);
#endif
}

#endif
