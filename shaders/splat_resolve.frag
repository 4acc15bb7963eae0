#version 460
// Resolve of normalised blending: the accumulated splats (rgb: sum of w c, a: sum of w, with
// w = -ln(1 - alpha)) become one premultiplied colour blended over the target: their weighted
// mean, at a coverage that grows with the summed weights.
layout(set = 0, binding = 0) uniform sampler2D accumulated;
layout(location = 0) out vec4 out_color;

// The weights add like log transmittances: 1 - exp(-sum) would be the coverage of the same
// splats composited "over". But a sampled surface is opaque between its samples, where that
// leaves it translucent: midway between three splats 1.4 standard deviations away the sum is
// about 1.2 (70 %), and the background showed through as dark blotches all over the default
// balloon. Four times the sum makes the surface opaque wherever two fringes overlap and still
// fades it out over about one standard deviation past the outermost centres (the silhouette).
const float k_coverage_gain = 4.0;

void main() {
    const vec4 sum = texelFetch(accumulated, ivec2(gl_FragCoord.xy), 0);
    if (!(sum.a > 1e-4)) discard;  // no splat here (or a NaN): the target shows through
    const float coverage = 1.0 - exp(-k_coverage_gain * sum.a);
    out_color = vec4(sum.rgb / sum.a * coverage, coverage);
}
