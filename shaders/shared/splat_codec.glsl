// Decoding of the packed Gaussian record's fields, shared by every splat path.
#ifndef PBDSPLAT_SPLAT_CODEC_GLSL
#define PBDSPLAT_SPLAT_CODEC_GLSL

// Octahedral unit vector (two snorm16), as splat::encode_octahedral writes it.
vec3 decode_octahedral(vec2 e) {
    vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
    if (n.z < 0.0) n.xy = (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
    return normalize(n);
}

// Opacity from its logit (eq. 21).
float sigmoid(float o) { return 1.0 / (1.0 + exp(-o)); }

#endif
