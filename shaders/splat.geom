#version 460
// Splat pass, geometry-shader path: see shared/splat_geometry.glsl.
#include "splat_geometry.glsl"
