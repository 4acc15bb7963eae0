// Textured splats (gpu_types.h, "Textured splats"): a splat of a textured model reads the
// texture under each of its pixels, its coordinates carried on from its centre along the
// surface, so the texture's detail is drawn at the pixel's scale, not blurred over the sample
// spacing. The front stage works out each carrier corner's coordinates; they are affine in the
// corner's place in the splat's tangent plane, so interpolating them is exact.
// Needs `frame` before inclusion.
#ifndef PBDSPLAT_SPLAT_TEXTURE_GLSL
#define PBDSPLAT_SPLAT_TEXTURE_GLSL

#include "splat_stream_order.glsl"

// How many textures binding 7 holds (0: none): only those are read.
layout(constant_id = 8) const uint k_texture_count = 0u;
const bool k_textured = k_texture_count > 0u;
layout(set = 0, binding = 6, std430) readonly buffer Texcoords { uint texcoord_words[]; };

struct SplatTexcoord {
    vec2 uv;
    vec3 du, dv;     // world gradients of u and v
    float texture;   // into binding 7, or -1: the record's own colour
    float reach;     // how far from its centre it may read (world units; short of a seam)
    vec3 tint;       // what the texture multiplies
};

SplatTexcoord read_texcoord(uint drawn) {
    SplatTexcoord t;
    t.texture = -1.0;
    if (!k_textured) return t;
    const uint base = stream_entry(drawn) * (SPLAT_TEXCOORD_SIZE / 4);
    const uint which = texcoord_words[base + 5u] & 0xFFFFu;
    t.reach = unpackHalf2x16(texcoord_words[base + 5u]).y;
    if (which == SPLAT_NO_TEXTURE) return t;
    t.uv = vec2(uintBitsToFloat(texcoord_words[base]), uintBitsToFloat(texcoord_words[base + 1u]));
    const vec2 a = unpackHalf2x16(texcoord_words[base + 2u]), b = unpackHalf2x16(texcoord_words[base + 3u]),
               c = unpackHalf2x16(texcoord_words[base + 4u]);
    t.du = vec3(a, b.x);
    t.dv = vec3(b.y, c);
    t.texture = float(which);
    t.tint = unpackUnorm4x8(texcoord_words[base + 6u]).rgb;
    return t;
}

// (u, v, texture) at a carrier corner: where the view ray through it meets the splat's tangent
// plane (as corner_normal() finds it), seen at a grazing angle no farther than about three
// times the carrier's reach. z < 0: the splat is not textured. (Carried on along the ray to
// where the surface curves away from the plane, by the record's curvature, the colour error
// against the textured mesh rose by half on a globe: the plane is what the splat draws.)
vec3 corner_texcoord(SplatTexcoord t, vec3 n, vec3 centre_world, vec3 corner_world) {
    if (!(t.texture >= 0.0)) return vec3(0.0, 0.0, -1.0);
    const vec3 d = corner_world - centre_world;
    const vec3 v = normalize(frame.camera_pos.xyz - centre_world);
    const float nv = dot(n, v);
    const float nv_safe = nv >= 0.0 ? max(nv, 0.3) : min(nv, -0.3);
    const vec3 p = d - v * (dot(n, d) / nv_safe);
    return vec3(t.uv + vec2(dot(t.du, p), dot(t.dv, p)), t.texture);
}

// What the fragment stage needs to keep the read short of a seam: the centre's coordinates and
// how far from the centre it may read (world units), and the metric that turns a change of the
// coordinates back into a distance along the surface (the inverse of the gradients' Gram matrix:
// xx, xy, yy).
vec3 texcoord_centre(SplatTexcoord t) { return vec3(t.uv, t.texture >= 0.0 ? t.reach : 0.0); }
vec3 texcoord_metric(SplatTexcoord t) {
    if (!(t.texture >= 0.0)) return vec3(0.0);
    const float a = dot(t.du, t.du), b = dot(t.du, t.dv), c = dot(t.dv, t.dv), det = a * c - b * b;
    return det > 0.0 ? vec3(c, -b, a) / det : vec3(0.0);
}

// The colour the splat stands for before its texture: the tint where textured, else `albedo`.
vec3 textured_albedo(SplatTexcoord t, vec3 albedo) { return t.texture >= 0.0 ? t.tint : albedo; }

#endif
