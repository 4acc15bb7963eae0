#version 460
// Splat pass, accumulation stage of normalised blending: every fragment of the front surface
// (those the visibility pass's depth lets through) adds its shaded colour and its weight into a
// float target; the resolve pass divides. Where discs overlap, the colour at a pixel is then a
// smooth mix of all of them rather than the nearest one's or the last drawn one's, so no disc's
// rim shows (see shared/splat_fragment.glsl).
layout(early_fragment_tests) in;

#define PBDSPLAT_WEIGHTED_OUTPUT
#include "splat_fragment.glsl"
