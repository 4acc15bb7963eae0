// Decoding of the packed Gaussian record's fields, shared by every splat path.
#ifndef PBDSPLAT_SPLAT_CODEC_GLSL
#define PBDSPLAT_SPLAT_CODEC_GLSL

// Octahedral unit vector (two snorm16), as splat::encode_octahedral writes it.
vec3 decode_octahedral(vec2 e) {
    vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
    if (n.z < 0.0) n.xy = (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
    return normalize(n);
}

// The record's symmetric curvature from its six halves (xx, xy, xz, yy | yz, zz).
mat3 splat_curvature(vec4 a, vec2 b) { return mat3(a.x, a.y, a.z, a.y, a.w, b.x, a.z, b.x, b.y); }

// An orthonormal tangent frame about n (the surfel's axes).
void splat_tangent_frame(vec3 n, out vec3 t1, out vec3 t2) {
    t1 = normalize(cross(n, abs(n.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0)));
    t2 = cross(n, t1);
}

// Opacity from its logit (eq. 21).
float sigmoid(float o) { return 1.0 / (1.0 + exp(-o)); }

#endif
