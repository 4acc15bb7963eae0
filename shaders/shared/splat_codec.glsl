// Decoding of the packed Gaussian record's fields, shared by every splat path.
#ifndef PBDSPLAT_SPLAT_CODEC_GLSL
#define PBDSPLAT_SPLAT_CODEC_GLSL

// Octahedral unit vector (two snorm16), as splat::encode_octahedral writes it.
vec3 decode_octahedral(vec2 e) {
    vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
    if (n.z < 0.0) n.xy = (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
    return normalize(n);
}

// The record's model (gpu_types.h: the lowest two bits of each normal component), from the
// normal's two snorm16 as read through a vertex attribute, and from its raw word.
uint splat_model_of(vec2 oct) {
    const ivec2 c = ivec2(round(oct * 32767.0));
    return uint(c.x & 3) | (uint(c.y & 3) << 2);
}
uint splat_model_bits(uint word) { return (word & 3u) | (((word >> 16) & 3u) << 2); }

// The record's symmetric curvature S from its 2x2 block (c.xyz on axes i, j) and the axis d it
// leaves out (c.w), with S n = 0 (splat::decode_curvature on the CPU).
mat3 splat_curvature(vec4 c, vec3 n) {
    if (c.xyz == vec3(0.0)) return mat3(0.0);
    const int d = min(int(c.w + 0.5) & 3, 2), i = (d + 1) % 3, j = (d + 2) % 3;
    const float id = -(c.x * n[i] + c.y * n[j]) / n[d], jd = -(c.y * n[i] + c.z * n[j]) / n[d];
    mat3 s;
    s[i][i] = c.x;
    s[j][j] = c.z;
    s[d][d] = -(id * n[i] + jd * n[j]) / n[d];
    s[i][j] = c.y;
    s[j][i] = c.y;
    s[i][d] = id;
    s[d][i] = id;
    s[j][d] = jd;
    s[d][j] = jd;
    return s;
}

// An orthonormal tangent frame about n (the surfel's axes).
void splat_tangent_frame(vec3 n, out vec3 t1, out vec3 t2) {
    t1 = normalize(cross(n, abs(n.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0)));
    t2 = cross(n, t1);
}

// The splat's place in the thinning order (surface/thin_order.h), stored above the curvature's
// left-out axis: x its level, y its rank within the level in (0, 1).
vec2 splat_thin_place(vec4 c) {
    const int packed = int(c.w + 0.5);
    return vec2(float(SPLAT_THIN_LEVELS - ((packed >> 2) & 7)), (float(packed >> 5) + 0.5) / 64.0);
}

// Opacity from its logit (eq. 21).
float sigmoid(float o) { return 1.0 / (1.0 + exp(-o)); }

#endif
