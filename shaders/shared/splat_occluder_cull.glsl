// Against mesh occluders, a splat lying wholly behind the surface the mesh shows (the far side of
// a body, a piece behind another) has every fragment discarded by the fragment stage's test
// (splat_fragment.glsl); on a CPU rasteriser setting up its carrier and testing its pixels still
// cost most of the pass. The front stage drops it when the occluders' distance image, read at
// the carrier's corners, the midpoints of its sides and its centre, shows a surface nearer than
// the carrier's nearest corner by more than the tolerance at every one of them. A carrier holds
// no pixel outside its corners, and its distance along the view axis is never below its nearest
// corner's, so only a gap in the surface narrower than half the carrier, between the points read,
// could have shown a fragment.
// Needs `frame` and splat_footprint.glsl before inclusion.
#ifndef PBDSPLAT_SPLAT_OCCLUDER_CULL_GLSL
#define PBDSPLAT_SPLAT_OCCLUDER_CULL_GLSL

layout(set = 1, binding = 0) uniform sampler2D occluder_depth;

// Whether the occluders hide the whole of the screen point `clip` (pixel in the distance image),
// for a splat whose nearest point lies `nearest` along the view axis.
bool occluder_hides(vec4 clip, float nearest) {
    if (!(clip.w > 1e-6)) return false;
    const ivec2 last = textureSize(occluder_depth, 0) - 1;
    const vec2 ndc = clip.xy / clip.w;
    const ivec2 pixel = clamp(ivec2(floor((ndc * 0.5 + 0.5) * frame.viewport.xy)), ivec2(0), last);
    const float surface = texelFetch(occluder_depth, pixel, 0).r;
    return surface > 0.0 && nearest - surface > frame.visibility.w;
}

bool splat_hidden(SplatQuad q, vec3 world) {
    if (!(frame.visibility.w > 0.0)) return false;
    float nearest = 1e30;
    for (int i = 0; i < k_carrier_corners; ++i) {
        vec4 clip;
        vec3 corner_world;
        vec2 uv;
        float depth;
        splat_corner(q, world, i, clip, corner_world, uv, depth);
        if (!(clip.w > 1e-6)) return false;  // reaching behind the eye
        nearest = min(nearest, depth);
    }
    // The square [-1, 1]^2 bounds either carrier: its corners, its sides' midpoints, its centre.
    for (int y = -1; y <= 1; ++y)
        for (int x = -1; x <= 1; ++x)
            if (!occluder_hides(frame.proj * vec4(q.centre + float(x) * q.axis_right + float(y) * q.axis_up, 1.0), nearest)) return false;
    return true;
}

#endif
