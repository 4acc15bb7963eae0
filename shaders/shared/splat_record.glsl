// The Gaussian records as a storage buffer of 32-bit words, for the paths that pull them
// (mesh shader, vertex pulling) instead of taking them as vertex attributes.
#ifndef PBDSPLAT_SPLAT_RECORD_GLSL
#define PBDSPLAT_SPLAT_RECORD_GLSL

#include "splat_codec.glsl"

layout(set = 0, binding = 2, std430) readonly buffer Records { uint record_words[]; };

struct SplatRecord {
    vec3 position;
    vec3 normal;
    vec4 color;
    float scale;
    float opacity_logit;
    mat3 curvature;  // S: a step p in the tangent plane turns the normal by S p
    vec2 thin;  // its place in the thinning order (splat_thin_place)
    uint model;  // whose centre its environment lookups look out from
};

SplatRecord read_record(uint i) {
    const uint base = i * (SPLAT_RECORD_SIZE / 4);
    SplatRecord r;
    r.position = vec3(uintBitsToFloat(record_words[base + 0]), uintBitsToFloat(record_words[base + 1]),
                      uintBitsToFloat(record_words[base + 2]));
    const uint normal_word = record_words[base + SPLAT_OFFSET_NORMAL / 4];
    r.normal = decode_octahedral(unpackSnorm2x16(normal_word));
    r.model = splat_model_bits(normal_word);
    r.color = unpackUnorm4x8(record_words[base + SPLAT_OFFSET_COLOR / 4]);
    const vec2 so = unpackHalf2x16(record_words[base + SPLAT_OFFSET_SCALE_OPACITY / 4]);
    r.scale = so.x;
    r.opacity_logit = so.y;
    const uint c = base + SPLAT_OFFSET_CURVATURE / 4;
    const vec4 packed = vec4(unpackHalf2x16(record_words[c]), unpackHalf2x16(record_words[c + 1u]));
    r.curvature = splat_curvature(packed, r.normal);
    r.thin = splat_thin_place(packed);
    return r;
}

#endif
