#version 460
// The geometry-shader path against mesh occluders (render.visibility = "mesh"): as splat.geom,
// dropping the splats that the fragment stage would discard whole (shared/splat_occluder_cull.glsl).
#define PBDSPLAT_OCCLUDERS
#include "splat_geometry.glsl"
