#version 460
// Resolve of normalised blending: the accumulated splats (rgb: sum of w c, a: sum of w, with
// w = -ln(1 - alpha)) become one premultiplied colour blended over the target: their weighted
// mean, at a coverage that grows with the summed weights.
layout(set = 0, binding = 0) uniform sampler2D accumulated;         // the seen side's sums
layout(set = 0, binding = 1) uniform sampler2D accumulated_inside;  // an open body's inside
layout(location = 0) out vec4 out_color;

// The weights add like log transmittances: 1 - exp(-sum) would be the coverage of the same
// splats composited "over". But a sampled surface is opaque between its samples, where that
// leaves it translucent: midway between three splats 1.4 standard deviations away the sum is
// about 1.2 (70 %), and the background showed through as dark blotches all over the default
// balloon. Four times the sum makes the surface opaque wherever two fringes overlap and still
// fades it out over about one standard deviation past the outermost centres (the silhouette).
const float k_coverage_gain = 4.0;
// How fast the seen side's colour takes over from the inside's as its weight grows: a fringe of
// weight 0.1 (one splat's alpha 0.1) already decides 80 % of the colour, so a gap between the
// outer surface's opaque cores shows the outer surface around it rather than the inside behind.
const float k_seen_side_gain = 16.0;

void main() {
    const ivec2 p = ivec2(gl_FragCoord.xy);
    const vec4 seen = texelFetch(accumulated, p, 0), inside = texelFetch(accumulated_inside, p, 0);
    const float total = seen.a + inside.a;
    if (!(total > 1e-4)) discard;  // no splat here (or a NaN): the target shows through
    const float coverage = 1.0 - exp(-k_coverage_gain * total);
    const vec3 seen_mean = seen.a > 0.0 ? seen.rgb / seen.a : vec3(0.0);
    const vec3 inside_mean = inside.a > 0.0 ? inside.rgb / inside.a : vec3(0.0);
    const float t = inside.a > 0.0 ? 1.0 - exp(-k_seen_side_gain * seen.a) : 1.0;
    out_color = vec4(mix(inside_mean, seen_mean, t) * coverage, coverage);
}
