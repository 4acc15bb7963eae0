#version 460
// The paper's one pass against mesh occluders (render.visibility = "mesh"): as splat_paper.frag,
// keeping only the disc fragments that lie on the surface the mesh shows at their pixel (see
// shared/splat_fragment.glsl).
#define PBDSPLAT_OCCLUDERS
#include "splat_fragment.glsl"
