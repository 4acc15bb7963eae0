#version 460
// Normalised blending's accumulation stage against mesh occluders (render.visibility = "mesh"):
// as splat_accumulate.frag, keeping only the fragments that lie on the surface the mesh shows
// at their pixel (see shared/splat_fragment.glsl).
layout(early_fragment_tests) in;

#define PBDSPLAT_WEIGHTED_OUTPUT
#define PBDSPLAT_OCCLUDERS
#include "splat_fragment.glsl"
