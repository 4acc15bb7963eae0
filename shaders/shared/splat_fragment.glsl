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

void main() {
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
        if (off > frame.visibility.w || off < -2.0 * frame.visibility.w) discard;
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
    const vec3 albedo = mix(g_color.rgb, frame.interior.rgb, frame.interior.a * inside);
    const vec3 color = k_shade_per_corner ? g_color.rgb : shade(albedo, n, g_world);
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
